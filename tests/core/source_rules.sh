#!/bin/sh
# The tree's own rules, checked on the source (docs/DEVELOPING.md):
# no function in sim/ or app/ over 120 lines; no issue numbers in the
# documents, comments or data files; nothing points outside the repository
# (../shared); the simulation layer does not link or include the SHOL
# layer above it; one pilot-to-flight loop (sim_flight_step is called by
# the runner, sim/runner.c, and by the step the real-time loop wraps
# around it, sim/loop.c; nowhere else outside the tests and benchmarks).
# Usage: source_rules.sh SOURCE_DIR
set -u
src=$1
fail=0 pass=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $1"; fail=$((fail + 1)); }
cd "$src" || exit 1
# functions over 120 lines: from a line opening at column 0 with '{' to
# the next '}' at column 0
long=$(for f in sim/*.c app/*.c; do
    awk -v f="$f" '/^\{/ {s = NR; name = prev} /^\}/ && s {if (NR - s > 120) print f ":" s ": " NR - s " lines: " name; s = 0}
        {if ($0 !~ /^[ \t{]/ && $0 != "") prev = $0}' "$f"
done)
[ -z "$long" ] && ok || bad "functions over 120 lines in sim/ or app/:
$long"
files=$(git ls-files 2> /dev/null | grep -vE '^(\.git|tests/source_rules)' || find . -type f ! -path './.git/*')
hits=$(echo "$files" | grep -E '\.(c|h|md|ini|sh|txt|cff|cmake)$|CMakeLists' | grep -v '^tests/core/source_rules.sh$' \
    | xargs grep -nE '[Ii]ssues? ?#?[0-9]+\b' 2> /dev/null | grep -v '^docs/runs/')
[ -z "$hits" ] && ok || bad "issue numbers in the tree:
$hits"
hits=$(echo "$files" | grep -v '^tests/core/source_rules.sh$' | xargs grep -nE '\.\./shared|shared/(CONVENTIONS|reference)|\bCONVENTIONS\.md' 2> /dev/null)
[ -z "$hits" ] && ok || bad "paths outside the repository:
$hits"
grep -q 'disim_shol' sim/CMakeLists.txt && bad "sim/CMakeLists.txt links disim_shol" || ok
grep -lE '#include "(shol|couple)\.h"' sim/*.c sim/*.h 2> /dev/null | grep -q . && bad "sim/ includes shol.h or couple.h" || ok
callers=$(grep -lE '\bsim_flight_step\(' sim/*.c app/*.c couple/*.c 2> /dev/null | grep -vE '^sim/(flight|runner|loop)\.c$')
[ -z "$callers" ] && ok || bad "sim_flight_step called outside sim/runner.c and sim/loop.c: $callers"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
