#!/bin/sh
# disim check on the three kinds of file: it must say which kind it checked
# ("aircraft file PATH: NAME, ok"), name an unknown section in an aircraft and
# a ship file with its line, print a loader's warning and still pass, and
# refuse a unit slip; each with its exit status.
# Usage: cli_check_kind.sh DISIM_BINARY (run from the source root)
set -u
disim=$1
tmp=$(mktemp -d /tmp/cli_check_kind_XXXXXX) || exit 1
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0
# expect RC PATTERN FILE: exit status RC and PATTERN (grep -F) in stdout+stderr
expect() {
    want=$1 pat=$2 file=$3
    out=$("$disim" check "$file" 2>&1)
    rc=$?
    if [ $rc -eq "$want" ] && printf '%s\n' "$out" | grep -qF -- "$pat"; then
        pass=$((pass + 1))
    else
        fail=$((fail + 1))
        echo "FAIL check $file: exit $rc (expected $want), expected '$pat' in:"
        printf '%s\n' "$out" | tail -n 5
    fi
}
expect 0 "aircraft file scenarios/aircraft/uh60a.ini: UH-60A, ok" scenarios/aircraft/uh60a.ini
expect 0 "aircraft file scenarios/aircraft/sa365n.ini: SA365N, ok" scenarios/aircraft/sa365n.ini
expect 0 "aircraft file tests/hfm/data/luh25.ini: LUH-25, ok" tests/hfm/data/luh25.ini
expect 0 "ship file scenarios/ships/cg47.ini: CG-47, ok" scenarios/ships/cg47.ini
expect 0 "ship file scenarios/ships/sfs2.ini: SFS2, ok" scenarios/ships/sfs2.ini
expect 0 "scenario file scenarios/cg47_uh60a.ini: cg47_uh60a, ok" scenarios/cg47_uh60a.ini
# the good files print no warning
for f in scenarios/aircraft/uh60a.ini scenarios/aircraft/sa365n.ini tests/hfm/data/luh25.ini \
         scenarios/ships/cg47.ini scenarios/ships/lpd17.ini scenarios/ships/sfs2.ini scenarios/cg47_uh60a.ini; do
    if "$disim" check "$f" 2>&1 >/dev/null | grep -q warning; then
        fail=$((fail + 1)); echo "FAIL check $f: a warning on a good file"
    else pass=$((pass + 1)); fi
done
# unknown sections, named with file and line
n=$(($(wc -l < scenarios/aircraft/uh60a.ini) + 2)) # the line of its first key
{ cat scenarios/aircraft/uh60a.ini; printf '[foo]\nbar = 1\n'; } > "$tmp/ac_foo.ini"
expect 1 "$tmp/ac_foo.ini:$n: unknown section [foo]" "$tmp/ac_foo.ini"
n=$(($(wc -l < scenarios/ships/cg47.ini) + 2))
{ cat scenarios/ships/cg47.ini; printf '[blok mast]\nx_m = 0, 1\n'; } > "$tmp/ship_blok.ini"
expect 1 "$tmp/ship_blok.ini:$n: unknown section [blok mast]" "$tmp/ship_blok.ini"
# warnings pass with exit 0; refusals exit 1
sed 's/^mass_kg = 2500.0 /mass_kg = 5512 /; s/^collective_deg_per_in = 1.6/collective_deg_per_in = 2.0/' \
    tests/hfm/data/luh25.ini > "$tmp/ac_lb.ini"
expect 0 "warning: $tmp/ac_lb.ini:" "$tmp/ac_lb.ini"
expect 0 "CT/sigma = 0.143" "$tmp/ac_lb.ini"
sed 's/^twist_deg = -10.0 /twist_deg = -0.1745 /' tests/hfm/data/luh25.ini > "$tmp/ac_rad.ini"
expect 1 "[main_rotor] twist_deg = -0.1745: a blade twist below 1 deg" "$tmp/ac_rad.ini"
sed 's/^deck_height_m = 8.0 /deck_height_m = 9.0 /' scenarios/ships/cg47.ini > "$tmp/ship_deck.ini"
expect 0 "warning: $tmp/ship_deck.ini:13: [ship] deck_height_m = 9: the blocks under the landing spot reach 8 m" \
    "$tmp/ship_deck.ini"
sed 's/^anemometer_S_m = 85, 0, -30/anemometer_S_m = 85, 0, 30/' scenarios/ships/cg47.ini > "$tmp/ship_anem.ini"
expect 1 "$tmp/ship_anem.ini:16: [ship] anemometer_S_m: z = 30 m is 22 m below the waterline" "$tmp/ship_anem.ini"
echo "cli_check_kind: $pass passed, $fail failed"
[ $fail -eq 0 ]
