"""One BLAS thread for the tool's own numerical work.

numpy and SciPy each bring an OpenBLAS whose worker threads busy-wait for work between calls.
The tool's fits are many small problems (SciPy's L-BFGS-B calls BLAS on every iteration of a
2- or 3-parameter fit), where those threads buy nothing and, on a machine whose cores are busy,
cost a great deal: each hand-off waits for a worker to be scheduled. Measured on 2 cores with a
CPU hog beside it, ``tactile analyze`` of a 12-participant study took 92 s with the default
threads and 25 s with one (4.1 s of CPU against 0.64 s for five psychometric fits).
:func:`one_blas_thread` limits every BLAS library loaded in the process to one thread while its
block runs (threadpoolctl), and the command line runs every command inside it.
"""

from __future__ import annotations

import contextlib


@contextlib.contextmanager
def one_blas_thread():
    """Limit the BLAS libraries loaded in this process to one thread inside the block."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # a stripped-down install: run as is
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield
