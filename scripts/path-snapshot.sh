#!/usr/bin/env bash
# Paths of every bundled scene and map, for checking that a refactoring changes no result.
#
#   scripts/path-snapshot.sh OUT_DIR            # write one paths file per scene/map
#   scripts/path-snapshot.sh --compare A B      # compare two snapshots (points to 1e-9)
#
# Each file holds, per path, its status and points (a configuration space's poses or joints)
# as `plan --json` reports them. Run it
# before and after a change, on the same machine, and compare. Needs jq and a release build
# of hplan (HPLAN, default target/release/hplan). me766_3d.json (5.6 M tetrahedra) is left
# out unless SNAPSHOT_LARGE=1.
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${1:-}" == "--compare" ]]; then
    a=$2 b=$3 bad=0
    for f in "$a"/*.json; do
        g="$b/$(basename "$f")"
        if [[ ! -f "$g" ]]; then echo "missing in $b: $(basename "$f")"; bad=1; continue; fi
        # Largest coordinate difference over all points, or "shape" when counts or statuses differ.
        d=$(jq -n --slurpfile x "$f" --slurpfile y "$g" '
            def flat: [.[] | .status, (.points | length)];
            if ($x[0] | flat) != ($y[0] | flat) then "shape"
            else [ [$x[0], $y[0]] | transpose[] | [.[0].points, .[1].points] | transpose[]
                   | [.[0], .[1]] | transpose[] | (.[0] - .[1]) | fabs ] | (max // 0) end')
        if [[ "$d" == '"shape"' ]] || jq -e -n "$d > 1e-9" > /dev/null; then
            echo "$(basename "$f"): differs ($d)"; bad=1
        else
            echo "$(basename "$f"): same (largest difference $d)"
        fi
    done
    exit $bad
fi

out=${1:?usage: scripts/path-snapshot.sh OUT_DIR | --compare A B}
hplan=${HPLAN:-target/release/hplan}
mkdir -p "$out"
keep='[.paths[] | {status, points: (.points // .poses // .joints)}]'
for scene in meshes/*.json meshes/contract/*.json; do
    name=$(basename "$scene" .json)
    [[ "$name" == me766_3d && "${SNAPSHOT_LARGE:-0}" != 1 ]] && continue
    "$hplan" plan "$scene" --json | jq -c "$keep" > "$out/$name.json"
done
# The bundled maps, with the starts and goals the README uses.
"$hplan" plan --map meshes/warehouse_map.yaml --goal 16.5,1.5 --robot-radius 0.2 \
    --start=-0.75,-0.5 --start 3.0,4.0 --start 7.0,12.0 --start 13.0,8.5 --json \
    | jq -c "$keep" > "$out/warehouse_map.json"
"$hplan" plan --map meshes/warehouse_map.yaml --goal 16.5,1.5 --robot-radius 0.2 --mesher quadtree \
    --start=-0.75,-0.5 --start 3.0,4.0 --start 7.0,12.0 --start 13.0,8.5 --json \
    | jq -c "$keep" > "$out/warehouse_map_quadtree.json"
for w in 0 1 4; do
    "$hplan" plan --map meshes/costly_band.yaml --goal 7.5,2.0 --cost-weight $w \
        --start 0.5,0.5 --start 0.5,1.0 --start 0.5,2.0 --start 0.5,3.5 --json \
        | jq -c "$keep" > "$out/costly_band_w$w.json"
done
echo "wrote $(ls "$out" | wc -l) path files to $out"
