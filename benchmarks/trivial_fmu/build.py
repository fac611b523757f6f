"""Build the trivial FMU (FMI 2 or 3 co-simulation): the floor of benchmarks/bench_native_fmu.py.

    python benchmarks/trivial_fmu/build.py OUT_DIR      # writes trivial2.fmu and trivial3.fmu

One state, dx/dt = -k x, stepped exactly (decay.c); built the way gear_dyn's native FMU is built
(:func:`gear_dyn.fmu.toolchain.compile_binaries`: the system compiler, libm only, a Windows DLL
where MinGW-w64 is installed) and shipping its sources (FMI 2 ``SourceFiles``, FMI 3
``sources/buildDescription.xml``).
"""

from __future__ import annotations

import sys
import tempfile
import zipfile
from pathlib import Path

from gear_dyn.fmu.toolchain import compile_binaries, fmi_headers

HERE = Path(__file__).resolve().parent
IDENTIFIER = "trivial_decay"
#: the instantiation token (DECAY_GUID in decay.h)
GUID = "{5e1f6c0a-9d27-4b8e-a0c3-7d2b1f4e8a61}"
MODEL = ("decay.h", "decay.c")
GLUE = {2: "fmi2_glue.c", 3: "fmi3_glue.c"}
#: the output, its start value and the parameter (value reference, name)
X, K = (1, "x"), (2, "k")

_MD2 = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="trivial_decay" guid="{GUID}"
  description="dx/dt = -k x, stepped exactly: the floor of gear_dyn's FMU benchmark"
  generationTool="gear_dyn benchmarks/trivial_fmu" variableNamingConvention="flat"
  numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{IDENTIFIER}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUstate="true" canSerializeFMUstate="true">
    <SourceFiles>
      <File name="decay.c"/>
      <File name="fmi2_glue.c"/>
    </SourceFiles>
  </CoSimulation>
  <UnitDefinitions>
    <Unit name="1/s"><BaseUnit s="-1"/></Unit>
  </UnitDefinitions>
  <DefaultExperiment startTime="0" stopTime="1" stepSize="0.01"/>
  <ModelVariables>
    <ScalarVariable name="{X[1]}" valueReference="{X[0]}" causality="output"
      variability="continuous" initial="exact" description="the state">
      <Real start="1"/>
    </ScalarVariable>
    <ScalarVariable name="{K[1]}" valueReference="{K[0]}" causality="parameter"
      variability="fixed" initial="exact" description="decay rate">
      <Real unit="1/s" start="1" min="0" max="1e6" nominal="1"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="1" dependencies=""/></Outputs>
  </ModelStructure>
</fmiModelDescription>
"""

_MD3 = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="trivial_decay" instantiationToken="{GUID}"
  description="dx/dt = -k x, stepped exactly: the floor of gear_dyn's FMU benchmark"
  generationTool="gear_dyn benchmarks/trivial_fmu" variableNamingConvention="flat">
  <CoSimulation modelIdentifier="{IDENTIFIER}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUState="true" canSerializeFMUState="true"/>
  <UnitDefinitions>
    <Unit name="1/s"><BaseUnit s="-1"/></Unit>
  </UnitDefinitions>
  <DefaultExperiment startTime="0" stopTime="1" stepSize="0.01"/>
  <ModelVariables>
    <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
    <Float64 name="{X[1]}" valueReference="{X[0]}" causality="output" variability="continuous"
      initial="exact" start="1" description="the state"/>
    <Float64 name="{K[1]}" valueReference="{K[0]}" causality="parameter" variability="fixed"
      initial="exact" start="1" min="0" max="1e6" nominal="1" unit="1/s"
      description="decay rate"/>
  </ModelVariables>
  <ModelStructure>
    <Output valueReference="{X[0]}" dependencies=""/>
  </ModelStructure>
</fmiModelDescription>
"""

_BUILD3 = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiBuildDescription fmiVersion="3.0">
  <BuildConfiguration modelIdentifier="{IDENTIFIER}">
    <SourceFileSet language="C99">
      <SourceFile name="decay.c"/>
      <SourceFile name="fmi3_glue.c"/>
    </SourceFileSet>
  </BuildConfiguration>
</fmiBuildDescription>
"""


def build_trivial_fmu(out: str | Path, fmi: int = 2) -> Path:
    """Write the trivial FMU (FMI ``fmi`` = 2 or 3) to ``out`` and return its path.

    Raises
    ------
    InputError
        No C compiler.
    RuntimeError
        The compiler failed.
    """
    out = Path(out)
    sources = [HERE / name for name in (*MODEL, GLUE[fmi])]
    with tempfile.TemporaryDirectory(prefix="trivial_fmu_") as tmp:
        binaries = compile_binaries([s for s in sources if s.suffix == ".c"], Path(tmp),
                                    IDENTIFIER, fmi=fmi, include_dirs=[fmi_headers(fmi), HERE])
        out.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("modelDescription.xml", _MD2 if fmi == 2 else _MD3)
            for platform, lib in binaries.items():
                z.write(lib, f"binaries/{platform}/{lib.name}")
            for s in sources:
                z.write(s, f"sources/{s.name}")
            if fmi == 3:
                z.writestr("sources/buildDescription.xml", _BUILD3)
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python benchmarks/trivial_fmu/build.py OUT_DIR")
    for version in (2, 3):
        print(build_trivial_fmu(Path(sys.argv[1]) / f"trivial{version}.fmu", version))
