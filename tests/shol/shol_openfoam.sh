#!/bin/sh
# disim shol with [cfd] engine = openfoam: the sweep starts an OpenFOAM
# builder (disim airwaked --engine openfoam --np 2) on its database, which
# it claims for OpenFOAM (DB/engine); the envelope is written and its
# report names the engine and the field's state. The same sweep with the
# embedded engine on that database stops with both engines named and
# writes nothing. Skips (77) without OpenFOAM or mpirun (fails under CI).
# Usage: shol_openfoam.sh DISIM SOURCE_DIR
set -u
. "$(dirname "$0")/../skip.sh"
disim=$1 src=$2
command -v simpleFoam > /dev/null || skip shol_openfoam "OpenFOAM's simpleFoam is not on PATH (go.sh installs openfoam)"
command -v mpirun > /dev/null || skip shol_openfoam "mpirun is not on PATH (go.sh installs openmpi-bin)"
tmp=$(mktemp -d /tmp/disim_shol_foam_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
scen=$src/tests/shol/data/openfoam_sfs2.ini
TMPDIR=$tmp "$disim" shol "$scen" --cfd-max-iter 40 -o "$tmp/o" --db "$tmp/db" > "$tmp/o.out" 2> "$tmp/o.err" \
    || { echo "the OpenFOAM sweep failed"; tail -20 "$tmp/o.err"; tail -20 "$tmp/db/builder.log"; exit 1; }
[ "$(cat "$tmp/db/engine")" = openfoam ] || { echo "the database is not claimed for openfoam"; fail=1; }
grep -q 'airwaked .*--engine\|openfoam v' "$tmp/db/builder.log" || { echo "the builder did not run OpenFOAM"; tail "$tmp/db/builder.log"; fail=1; }
grep -q '^1 field was solved by OpenFOAM v' "$tmp/o/report.md" || { echo "the report does not name OpenFOAM"; fail=1; }
grep -q '^0.000000,[0-9.]*,20.000000,none,' "$tmp/o/shol.csv" || { echo "shol.csv has no head-wind row open to 20 km/h"; cat "$tmp/o/shol.csv"; fail=1; }
[ -z "$(ls "$tmp" | grep '^disim-foam-')" ] || { echo "an OpenFOAM case folder was left behind"; fail=1; }
# the embedded engine on the OpenFOAM database: refused, nothing written
sed 's/^engine = openfoam/engine = embedded/; /^np = /d' "$scen" > "$tmp/emb.ini"
sed -i "s#\.\./\.\./\.\./#$src/#" "$tmp/emb.ini"
if "$disim" shol "$tmp/emb.ini" -o "$tmp/e" --db "$tmp/db" > "$tmp/e.out" 2> "$tmp/e.err"; then
    echo "the embedded sweep on the OpenFOAM database ran"; fail=1
fi
grep -q "holds the openfoam engine's fields.*embedded engine's" "$tmp/e.err" || { echo "expected both engines named:"; cat "$tmp/e.err"; fail=1; }
[ ! -e "$tmp/e/shol.csv" ] || { echo "the refused sweep wrote shol.csv"; fail=1; }
[ $fail -eq 0 ] && echo "shol_openfoam: passed"
exit $fail
