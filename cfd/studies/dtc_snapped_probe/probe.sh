#!/bin/bash
# Does interFoam (OpenFOAM v1912 as packaged by Debian) run on a snapped, layered DTC hull?
# Runs the DTCHull tutorial of openfoam-examples unchanged (its own blockMesh, six topoSet + refineMesh
# passes for the free-surface band, snappyHexMesh with 3 prism layers, setFields) except for the number of
# processors (2, simple decomposition: scotch is not in this build), then ITERATIONS (default 10) LTS
# iterations, and prints the continuity error and the hull force of each iteration.
#
# Usage: probe.sh OUT_DIR [laminar|noslip|pcg|predictor]
#   laminar    turbulence off           noslip     hull velocity noSlip (not movingWallVelocity)
#   pcg        p_rgh by PCG, not GAMG    predictor  momentumPredictor on
# Cost: about 4 min of meshing and 6 s of CPU per iteration (845 539 cells) on the 2-core machine.
set -eu
[ $# -ge 1 ] && [ $# -le 2 ] || { echo "usage: probe.sh OUT_DIR [laminar|noslip|pcg|predictor]" >&2; exit 2; }
OUT=$1
VARIANT=${2:-}
ITERATIONS=${ITERATIONS:-10}
export WM_PROJECT_DIR=${WM_PROJECT_DIR:-/usr/share/openfoam}
EXAMPLES=/usr/share/doc/openfoam-examples/examples
case "$VARIANT" in
  ""|laminar|noslip|pcg|predictor) ;;
  *) echo "probe.sh: unknown variant '$VARIANT' (laminar, noslip, pcg, predictor)" >&2; exit 2 ;;
esac
case "$ITERATIONS" in
  ''|*[!0-9]*|0) echo "probe.sh: ITERATIONS must be a whole number >= 1 (got '$ITERATIONS')" >&2; exit 2 ;;
esac
[ -e "$OUT" ] && { echo "probe.sh: $OUT exists; give a new folder" >&2; exit 2; }
[ -d "$EXAMPLES/multiphase/interFoam/RAS/DTCHull" ] || { echo "probe.sh: needs openfoam-examples" >&2; exit 2; }
cp -r "$EXAMPLES/multiphase/interFoam/RAS/DTCHull" "$OUT"
cd "$OUT"
[ -f system/snappyHexMeshDict.gz ] && gunzip system/snappyHexMeshDict.gz
mkdir -p constant/triSurface
cp "$EXAMPLES/resources/geometry/DTC-scaled.stl.gz" constant/triSurface/
sed -i 's/numberOfSubdomains 8;/numberOfSubdomains 2;/; s/method          scotch;/method          simple;/; s/n           (2 2 2);/n           (2 1 1);/' system/decomposeParDict
sed -i "s/^endTime .*/endTime         $ITERATIONS;/" system/controlDict
case "$VARIANT" in
  laminar) sed -i 's/simulationType.*/simulationType laminar;/' constant/turbulenceProperties ;;
  noslip) python3 - <<'PY'
import re
s = open("0.orig/U").read()
s = re.sub(r"(hull\s*\{\s*)type\s+movingWallVelocity;\s*value\s+uniform \(0 0 0\);", r"\1type noSlip;", s)
open("0.orig/U", "w").write(s)
PY
  ;;
  pcg) python3 - <<'PY'
s = open("system/fvSolution").read()
s = s.replace("p_rgh\n    {\n        solver          GAMG;\n\n        smoother        DIC;",
              "p_rgh\n    {\n        solver          PCG;\n        preconditioner  DIC;")
open("system/fvSolution", "w").write(s)
PY
  ;;
  predictor) sed -i 's/momentumPredictor   no;/momentumPredictor   yes;/' system/fvSolution ;;
esac
run() { local name=$1; shift; "$@" > "log.$name" 2>&1 || { echo "$name failed (log.$name)"; return 1; }; }
run surfaceFeatureExtract surfaceFeatureExtract
run blockMesh blockMesh
for i in 1 2 3 4 5 6; do
  run "topoSet.$i" topoSet -dict "system/topoSetDict.$i"
  run "refineMesh.$i" refineMesh -dict system/refineMeshDict -overwrite
done
run snappyHexMesh snappyHexMesh -overwrite
checkMesh > log.checkMesh 2>&1 || true
grep -E "^\s+cells:|Max skewness|non-orthogonality Max|Failed [0-9]+ mesh checks|Mesh OK" log.checkMesh || true
grep -A3 "^patch faces    layers   overall thickness" log.snappyHexMesh | tail -1 || true
rm -rf 0 && cp -r 0.orig 0
run setFields setFields
run decomposePar decomposePar -force
status=0
mpirun -np 2 --allow-run-as-root --oversubscribe interFoam -parallel > log.interFoam 2>&1 || status=$?
# one line per iteration: time, the second (final) continuity error of the step, the total hull force
awk '/^Time = /{t=$3} /time step continuity errors/{c=$9; sub(",", "", c)} /Total    :/&&!seen[t]++{print "iteration " t ": continuity sum local " c ", hull force (N) " $3, $4, $5}' log.interFoam
echo "interFoam exit code $status"
