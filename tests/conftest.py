import os
import sys

# Single-threaded BLAS, as the pipeline runs it (see pipeline.py): the tests are many small
# dense problems, for which threads only add contention.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

# Tests import the project's top-level packages from the checkout.
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
