"""The tolerance study's figure: the 5-95 % band and median of every figure against speed."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gear_dyn.plots._axes import axes_of, tidy

#: (metric, axis label, scale to the plotted unit)
_PANELS = (("peak_force", "peak mesh force / W", None),
           ("k_dyn", "K_dyn", 1.0),
           ("rms_dte", "RMS DTE (um)", 1e6))


def plot_tolerance(result: Any, ax: Any = None, iso_kv: Any = None) -> Any:
    """Median (line) and 5-95 % band (shaded) over the Monte-Carlo samples of the peak mesh
    force over W, K_dyn and the RMS DTE against pinion speed, with the response without
    deviations (dashed) and, on the K_dyn panel, ISO 6336-1 K_v at the same grade (``iso_kv``:
    an array over the result's speeds, dash-dot). The title states N and the largest
    Monte-Carlo standard error of the median K_dyn.

    Parameters
    ----------
    result : ToleranceResult
    ax : sequence of 3 Axes or None
        The caller's axes, or None for a new figure.
    iso_kv : array_like or None
        K_v at ``result.speeds``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axs = axes_of(ax, 3, 1, figsize=(8, 8), name="plot_tolerance", sharex=True)
    axs = np.ravel(axs)
    rpm = result.speeds * 60 / (2 * math.pi)
    for a, (metric, label, scale) in zip(axs, _PANELS, strict=True):
        s = 1.0 / result.static_load if scale is None else scale
        st = result.stats(metric)
        a.fill_between(rpm, st["p05"] * s, st["p95"] * s, color="tab:blue", alpha=0.25,
                       lw=0, label="5-95 % of samples")
        a.plot(rpm, st["median"] * s, color="tab:blue", lw=1.5, label="median")
        a.plot(rpm, result.baseline[metric] * s, color="0.3", ls="--", lw=1,
               label="no deviations")
        if metric == "k_dyn" and iso_kv is not None:
            a.plot(rpm, np.asarray(iso_kv, dtype=float), color="tab:red", ls="-.", lw=1,
                   label="ISO 6336-1 K_v (same grade)")
        a.set_ylabel(label)
        a.grid(True, alpha=0.3)
        a.legend(loc="upper left", fontsize=8)
    axs[-1].set_xlabel("pinion speed (rpm)")
    se = result.stats("k_dyn")["median_stderr"]
    error = (f"median K_dyn within +-{float(np.nanmax(se)):.2g} (1 s.e.)"
             if np.any(np.isfinite(se)) else "one sample: no Monte-Carlo error")
    axs[0].set_title(f"{result.name or 'tolerance study'}: N = {result.n_samples} samples over "
                     f"the hunting period ({result.hunting_period} mesh cycles); {error}",
                     fontsize=9)
    tidy(fig)
    return fig
