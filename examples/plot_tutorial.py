"""
Tutorial: from your own pair to a drivetrain FMU
================================================

This tutorial takes one gear pair of your own, a helical pair of a rail gearbox, from its scene
file to a run, a speed sweep, a design comparison, a tolerance study and an FMU placed between
two shafts of a drivetrain. Each step shows the command that does it from a terminal, the
Python call that does the same, the figure, and what to read off it. Every number on this page
is printed by the code when the page is built.

Run it yourself with ``python examples/plot_tutorial.py OUT_DIR``: the scene files, the FMU
and the figures are written into ``OUT_DIR``. The settings are kept short (few speeds, short
runs, few samples) so that the whole page builds in seconds; the commands give the settings
you would use for a design.
"""

# %%
# 1. A scene of your own
# ----------------------
#
# A scene is a TOML file: the gear data, the operating point, and optional tables for
# everything else. ``gear-dyn init my_pair.toml`` writes a commented starter file;
# ``gear-dyn scene keys`` lists every table and key with its unit and range. The pair here:
# 23/79 teeth, normal module 6 mm, normal pressure angle 20 deg, helix angle 20 deg, face
# width 70 mm, profile shifts +0.3 / -0.1, driven at 4000 rpm with 2000 N m on the pinion,
# made to ISO 1328-1 grade 6. Quantities carry their units; the grade goes into ``[iso]``,
# where ISO 6336-1 K_v and the tolerance study below take it from.

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from matplotlib.figure import Figure

import gear_dyn as gd
from gear_dyn.fmu.export_fmu import build_native_fmu
from gear_dyn.io import save_figure
from gear_dyn.plots.run import plot_time_history
from gear_dyn.plots.sweep import plot_sweep_response
from gear_dyn.plots.tolerance import plot_tolerance
from gear_dyn.scene import build_model, build_pair
from gear_dyn.scene.tolerance import tolerance_scene

# sphinx_gallery_thumbnail_number = 2
OUT = Path(sys.argv[1] if len(sys.argv) > 1 else "tutorial_out")
OUT.mkdir(parents=True, exist_ok=True)

SCENE = """\
[scene]
name = "rail_pair"
description = "Helical rail-gearbox pair, ISO grade 6"
model = "sdof"

[gear]
teeth_pinion = 23
teeth_gear = 79
module = "6 mm"            # normal module
pressure_angle = "20 deg"  # normal pressure angle
helix_angle = "20 deg"
face_width = "70 mm"
profile_shift_pinion = 0.3
profile_shift_gear = -0.1

[operating]
speed = "4000 rpm"         # pinion
torque = "2000 N*m"        # pinion

[iso]
accuracy_grade = 6
"""
scene_file = OUT / "rail_pair.toml"
scene_file.write_text(SCENE)
scene = gd.load_scene(scene_file)        # checks every key: unit, range, spelling
pair = build_pair(scene)                 # the GearPair: geometry, contact ratios
print(f"transverse contact ratio eps_alpha = {pair.contact_ratio:.3f}, "
      f"overlap ratio eps_beta = {pair.overlap_ratio:.3f}")

# %%
# 2. A run
# --------
#
# The command ``gear-dyn run rail_pair.toml --out run`` writes the time history, the spectrum
# and ``summary.json``. In Python, :func:`~gear_dyn.scene.run_scene` gives the result and
# :func:`~gear_dyn.analysis.report.summarize` its figures: the mesh frequency, the natural
# frequency of the mesh, the dynamic factor K_dyn (peak dynamic over peak quasi-static mesh
# force), the peak mesh force over the static load F_max / W and ISO 6336-1 K_v at the same
# grade. K_v builds in the pitch and profile deviations of the grade, which this run leaves
# out (the tolerance study below puts them in). No ``[stiffness]`` table: a helical pair gets
# the contact-line-length stiffness, and the summary says so.

result = gd.run_scene(scene, periods=40)      # 40 mesh periods here; the scene's default is 200
summary = gd.summarize(result)
print(f"stiffness: {summary['stiffness_choice']}")
print(f"f_m = {summary['mesh_frequency_hz']:.1f} Hz, f_n = {summary['natural_frequency_hz']:.1f} "
      f"Hz, K_dyn = {summary['dynamic_factor']:.4f}, F_max / W = "
      f"{summary['peak_force_ratio']:.4f}, ISO 6336-1 K_v = {summary['iso_6336_kv']['k_v']:.4f}")
fig = Figure(figsize=(9, 5.5), layout="constrained")     # a figure that reads at page width
plot_time_history(result, periods=5, ax=fig.subplots(2, 2))   # DTE, zoom; force, zoom
print("wrote", save_figure(fig, OUT / "run.png", dpi=90).name)

# %%
# Read the steady window (shaded) of the time history: the DTE and the mesh force oscillate
# about their static values at the mesh frequency, and the zoom on the right shows the last
# mesh periods. The figures printed above are taken over that window.

# %%
# 3. A speed sweep
# ----------------
#
# ``gear-dyn sweep rail_pair.toml --speeds "1000 rpm:9000 rpm:161" --out sweep`` computes the
# steady response at every speed (the periodic orbit, not a long transient) and writes the
# response curves with ISO K_v beside them. In Python:
# :func:`~gear_dyn.scene.sweep.sweep_scene`, here at 17 speeds.

SPEEDS = "1000 rpm:9000 rpm:17"
sweep = gd.sweep_scene(scene, SPEEDS)
peak = sweep.peak("peak_force_ratio")
resonance_rpm = sweep.natural_frequency / pair.z1 * 60      # where f_m = f_n
print(f"peak F_max / W = {peak.value:.4f} at {peak.speed_rpm:.0f} rpm; "
      f"f_m = f_n at {resonance_rpm:.0f} rpm")
print("wrote", save_figure(plot_sweep_response(sweep), OUT / "sweep.png", dpi=90).name)

# %%
# Read the speed of the peak against the speed where the mesh frequency meets the natural
# frequency (both printed above): the main resonance of the mesh lies there. The dotted lines
# mark where the second and third mesh harmonics meet it (f_m = f_n / 2, f_n / 3), the speeds
# of the secondary resonances. With 17 speeds the curve is coarse; the command's 161 speeds
# resolve the peaks.

# %%
# 4. A design comparison
# ----------------------
#
# Is another helix angle better? With an overlap ratio eps_beta of exactly 1 the total length
# of the contact lines, and with it the mesh stiffness, hardly varies over the mesh cycle. The
# helix angle that gives eps_beta = 1 on the 70 mm face is sin(beta) = pi m_n / b. A copy of the
# scene with that angle is the second design; ``gear-dyn compare rail_pair.toml
# rail_pair_eps1.toml --speeds "1000 rpm:9000 rpm:161" --out compare`` ranks the designs by
# their peak F_max / W over the range, the first file being the baseline. In Python:
# :func:`~gear_dyn.scene.compare.compare_scenes`.

beta_1 = math.degrees(math.asin(math.pi * 6.0 / 70.0))
variant_file = OUT / "rail_pair_eps1.toml"
variant_file.write_text(SCENE.replace('name = "rail_pair"', 'name = "rail_pair_eps1"')
                        .replace('helix_angle = "20 deg"', f'helix_angle = "{beta_1:.3f} deg"'))
comparison = gd.compare_scenes([scene_file, variant_file], SPEEDS)
print(f"helix angle for eps_beta = 1: {beta_1:.3f} deg")
print(comparison)                                  # the ranking, peaks and their differences
fig = Figure(figsize=(10, 6), layout="constrained")      # a figure that reads at page width
grid = fig.add_gridspec(2, 2, width_ratios=(1.6, 1.0))
force_ax = fig.add_subplot(grid[0, 0])
comparison.plot(ax=[force_ax, fig.add_subplot(grid[1, 0], sharex=force_ax),
                    fig.add_subplot(grid[:, 1])])
print("wrote", save_figure(fig, OUT / "compare.png", dpi=90).name)

# %%
# Read the ranking printed above: the design listed first has the lower peak F_max / W, and
# the bar chart gives each design's figures against the baseline's. The flags say when a
# peak lies at an end of the swept range, where the true peak may lie beyond it. Mind what
# the stiffness model leaves out: the contact-line length keeps no variation of the tooth's
# stiffness along its profile, so it credits an overlap ratio of 1 with more than a real
# flank gives; the slice loaded contact (``[lead_modification]``, ``[tip_relief]``,
# ``gear-dyn contact``) includes it.

# %%
# 5. A tolerance study
# --------------------
#
# Grade 6 allows pitch and profile deviations of several micrometres, and every gearbox has its
# own. ``gear-dyn tolerance SCENE --samples 200 --speeds "1000 rpm:9000 rpm:101" --out tol``
# draws random deviations within the grade (ISO 1328-1) and gives the band of the response
# over the samples beside the response without deviations. The study is exact over the whole
# hunting period for the linear model with piecewise-constant stiffness. The contact-line
# stiffness of this helical pair varies little about its mean (printed below), so the study's
# scene takes a constant stiffness of that mean (a ``[stiffness]`` table with
# ``method = "rectangular"`` and equal single and double values): what the band shows is then
# the deviations' own excitation. In Python:
# :func:`~gear_dyn.scene.tolerance.tolerance_scene`, here with 40 samples.

k_mesh = build_model(scene).stiffness           # the run's k(t): contact-line length
print(f"contact-line stiffness {k_mesh.min / k_mesh.mean:.3f}..{k_mesh.max / k_mesh.mean:.3f} "
      f"of its mean {k_mesh.mean / 1e6:.0f} N/um")
const_file = OUT / "rail_pair_constant_k.toml"
const_file.write_text(SCENE + f'''
[stiffness]
method = "rectangular"
single = "{k_mesh.mean:.6g} N/m"
double = "{k_mesh.mean:.6g} N/m"
''')
study = tolerance_scene(gd.load_scene(const_file), SPEEDS, samples=40)   # grade from [iso]
k = study.stats("k_dyn")
i = int(np.argmax(k["median"]))
print(f"{study.n_samples} samples, exact over the hunting period of "
      f"{study.hunting_period} mesh cycles")
print(f"largest median K_dyn {k['median'][i]:.4f} at {study.speeds[i] * 30 / math.pi:.0f} rpm, "
      f"5-95 % band {k['p05'][i]:.4f}-{k['p95'][i]:.4f}, without deviations "
      f"{study.baseline['k_dyn'][i]:.4f}")
apart = np.mean(study.values["min_force"][:, i] < 0)
print(f"at that speed the least mesh force is negative in {100 * apart:.0f} % of the samples "
      "(there the teeth would separate, which the linear model does not represent)")
print("wrote", save_figure(plot_tolerance(study), OUT / "tolerance.png", dpi=90).name)

# %%
# Read the width of the band against the line without deviations: where the band is wide, the
# response of a gearbox depends on how its own gears came out within the grade, and a design
# figure should be taken from the band rather than from the ideal pair. Where samples lose
# contact (the share printed above), the linear model does not hold: a scene with
# ``[backlash]`` follows the teeth apart, in runs and sweeps rather than in this study.

# %%
# 6. An FMU in a drivetrain
# -------------------------
#
# ``gear-dyn fmu build rail_pair.toml --ports torque --out rail_drive.fmu`` compiles a native
# FMI 2.0 co-simulation FMU of the pair with a torque input on each shaft and the angle and
# speed of each shaft out, with the mesh force and the DTE: it sits between a motor and a load
# in any FMI host. In Python: :func:`~gear_dyn.fmu.export_fmu.build_native_fmu`. Below, a small
# master loop in fmpy drives it: a constant motor torque of 2000 N m on the pinion and a load
# on the gear proportional to its speed, ``T2 = -c w2``, with c chosen so that the pair settles
# at 4000 rpm. The pair starts at 90 % of that speed.

fmu_file = build_native_fmu(scene_file, OUT / "rail_drive.fmu", ports="torque").path
md = read_model_description(fmu_file)
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_file, OUT / "rail_drive"),
                modelIdentifier=md.coSimulation.modelIdentifier, instanceName="rail")
fmu.instantiate()
t1 = 2000.0                                         # motor torque, N m
w0 = 4000 * math.pi / 30                            # operating pinion speed, rad/s
ratio = pair.z2 / pair.z1
c_load = t1 * ratio ** 2 / w0                       # -c w2 balances T1 z2/z1 at w2 = w0 / ratio
fmu.setReal([vr["pinion.torque"], vr["pinion.speed_start"]], [t1, 0.9 * w0])
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
i1, i2 = fmu.getReal([vr["inertia.pinion"], vr["inertia.gear"]])
tau = (i2 + i1 * ratio ** 2) / c_load              # time constant of the load, s
f_m = w0 * pair.z1 / (2 * math.pi)
h = 1 / (16 * f_m)                                  # 16 communication steps per mesh period
n = int(4 * tau / h)                                # four time constants
names = ["pinion.speed", "gear.speed", "mesh_force"]
rows = np.empty((n, len(names)))
for step in range(n):
    w2 = fmu.getReal([vr["gear.speed"]])[0]
    fmu.setReal([vr["gear.torque"]], [-c_load * w2])   # the load, held over the step
    fmu.doStep(currentCommunicationPoint=step * h, communicationStepSize=h)
    rows[step] = fmu.getReal([vr[v] for v in names])
fmu.terminate()
fmu.freeInstance()

t = np.arange(1, n + 1) * h
w1, w2, force = rows.T
load = t1 / pair.rb1                                # static mesh force at the motor torque, N
last = t > t[-1] - 20 / f_m                         # the last 20 mesh periods
print(f"load time constant {tau * 1e3:.1f} ms; after {t[-1] * 1e3:.0f} ms the pinion runs at "
      f"{w1[-1] * 30 / math.pi:.0f} rpm (speed ratio {np.mean(w1[last] / w2[last]):.4f}, "
      f"z2/z1 = {ratio:.4f}); mean mesh force over the last 20 mesh periods "
      f"{np.mean(force[last]) / load:.4f} T1 / r_b1")

# per 16 steps (a mesh period at 4000 rpm): the mean speed and the range of the mesh force
per = rows[: n - n % 16].reshape(-1, 16, len(names))
t_per = (np.arange(per.shape[0]) + 0.5) * 16 * h
fig = Figure(figsize=(9, 6.5), layout="constrained")
top, bottom = fig.subfigures(2, 1, height_ratios=[1, 1.1])
ax0 = top.subplots()
ax0.plot(t_per * 1e3, per[:, :, 0].mean(axis=1) * 30 / math.pi, label="pinion (mean over 16 steps)")
ax0.axhline(4000, color="0.5", ls="--", lw=1, label="4000 rpm: the load balances the motor")
ax0.set_ylabel("pinion speed (rpm)")
ax0.set_xlabel("time (ms)")
ax0.legend(loc="lower right")
ax1, ax2 = bottom.subplots(1, 2, width_ratios=[2, 1])
ax1.fill_between(t_per * 1e3, per[:, :, 2].min(axis=1) / load, per[:, :, 2].max(axis=1) / load,
                 color="tab:blue", alpha=0.3, lw=0, label="range over 16 steps")
ax1.plot(t_per * 1e3, per[:, :, 2].mean(axis=1) / load, color="tab:blue", label="mean")
ax1.axhline(1.0, color="0.5", ls="--", lw=1, label="T1 / r_b1")
ax1.set_ylabel("mesh force / (T1 / r_b1)")
ax1.set_xlabel("time (ms)")
ax1.legend(loc="lower right", fontsize=8)
zoom = t > t[-1] - 3 / f_m                          # the last 3 mesh periods
ax2.plot((t[zoom] - t[-1]) * 1e3, force[zoom] / load, ".-", ms=3, lw=0.8)
ax2.axhline(1.0, color="0.5", ls="--", lw=1)
ax2.set_xlabel("time before the end (ms)")
ax2.set_title("last 3 mesh periods", fontsize=9)
print("wrote", save_figure(fig, OUT / "drivetrain.png", dpi=90).name)

# %%
# Read the speed approaching the speed where the load balances the motor torque, within a few
# time constants of the load (printed above), and the mesh force oscillating at the mesh
# frequency about the force that transmits the motor torque. The same FMU runs in any FMI 2.0
# host, between shaft models of your own; ``gear-dyn fmu check rail_drive.fmu`` checks it.
