#!/bin/bash
# mpirun.sh ARGUMENTS...: mpirun as the tests start it: as root, with more
# ranks than cores, and with the ob1 point-to-point layer named, so that the
# ranks do not load the drivers of PSM and PSM2 interconnects to choose among
# the layers (what a serial run does too: app/mpi_start.h). A 2 x 2-cell scene
# on 2 ranks took a median of 0.86 s against 1.11 s for plain mpirun (a
# reviewer's alternating runs on the 2-core development VM, 2026-11-28). A
# value set in the environment, even an empty one, stays.
export OMPI_MCA_pml=${OMPI_MCA_pml-ob1}
exec mpirun --allow-run-as-root --oversubscribe "$@"
