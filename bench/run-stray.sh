#!/bin/sh
# A map with a stray feature (bench/README.md, "A stray edge far away"):
# hpfc-pack of a generated street network (bench/gen_streets.py) and of
# the same network with one short street far away (--stray), on one thread
# and on the default threads: wall and CPU time, peak resident memory, and
# the stray map's time over the plain map's. Validation's grid is cut at
# quantiles of the segments, so the stray edge should cost what the deeper
# tree costs the builder, not a validation of the whole network in one cell.
#   sh bench/run-stray.sh [POINTS ...]    default: 1e6 1e7
# Release build in build-bench/; the maps are generated once into
# build-bench/streets/.
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
pack=build-bench/hpfc-pack/hpfc-pack
dir=build-bench/streets
mkdir -p "$dir"
printf '%-6s %-6s %8s %9s %9s %9s  %s\n' points map threads wall_s cpu_s peak_MB "stray/plain (wall)"
for n in ${*:-1e6 1e7}; do
    [ -f "$dir/streets-$n.pfc" ] || python3 bench/gen_streets.py "$n" "$dir/streets-$n.pfc"
    [ -f "$dir/stray-$n.pfc" ] || python3 bench/gen_streets.py "$n" "$dir/stray-$n.pfc" --stray
    for threads in 1 0; do
        plain=
        for map in streets stray; do
            set -- -q --force
            [ "$threads" = 0 ] || set -- "$@" --threads "$threads"
            /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$pack" "$@" "$dir/$map-$n.pfc" -o "$dir/$map-$n.hpfc"
            read -r wall user sys kb <"$dir/time"
            ratio=$(python3 -c "print('%.2fx' % ($wall / $plain))" 2>/dev/null || true)
            [ -n "$plain" ] || plain=$wall
            printf '%-6s %-6s %8s %9.2f %9.2f %9.1f  %s\n' "$n" "$map" \
                "$([ "$threads" = 0 ] && echo default || echo "$threads")" "$wall" \
                "$(python3 -c "print($user + $sys)")" "$(python3 -c "print($kb / 1024)")" "$ratio"
        done
        rm -f "$dir/streets-$n.hpfc" "$dir/stray-$n.hpfc"
    done
done
