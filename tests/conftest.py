import os

# Single-threaded BLAS, as the pipeline runs it (see pipeline.py): the tests are many small
# dense problems, for which threads only add contention.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
