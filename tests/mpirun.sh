#!/bin/bash
# mpirun.sh ARGUMENTS...: mpirun as the tests start it, on this one machine:
# as root, more ranks than cores, and only the transports a single machine
# uses (shared memory and self). Open MPI otherwise also opens its TCP
# transport and the drivers of cluster interconnects on every rank, 0.2 s of
# each parallel test run (median of ten runs of a tiny scene on 2 ranks, 0.86 s
# against 0.66 s, by hand on the 2-core development VM, 2026-11-28). A value set
# in the environment stays.
export OMPI_MCA_btl=${OMPI_MCA_btl:-self,vader}
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
exec mpirun --allow-run-as-root --oversubscribe "$@"
