"""Limit BLAS worker threads before numpy loads.

gear_dyn works with 2x2..8x8 matrices: BLAS worker threads only add overhead, and on a busy
machine they oversubscribe the cores (measured with ``gear-dyn demo`` under load: the exact
propagator 15x slower with OpenBLAS threads). The limit is set only where the user has not
chosen one, and only takes effect when gear_dyn is imported before numpy.
"""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")
