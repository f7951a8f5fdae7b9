#!/bin/sh
# Build the example's two FMUs from their C sources (tests/fmus/msd_mass and msd_spring in a
# twinlink checkout) as the INTO-CPS example names them: MassSpringDamper1.fmu (the first
# mass) and MassSpringDamper2.fmu (the second mass and the coupling spring). They go into
# DIR (default: this folder, beside msd.json). Needs gcc; the same sources give the same bytes.
#
#   sh examples/cosim/build.sh [DIR]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-$here}
python=${PYTHON:-python3}
if [ -z "${PYTHON:-}" ] && [ -x "$root/.venv/bin/python" ]; then
  python="$root/.venv/bin/python"
fi
mkdir -p "$out"
"$python" -m twinlink.processors.fmubuild "$root/tests/fmus/msd_mass" "$out/MassSpringDamper1.fmu" --if-stale
"$python" -m twinlink.processors.fmubuild "$root/tests/fmus/msd_spring" "$out/MassSpringDamper2.fmu" --if-stale
