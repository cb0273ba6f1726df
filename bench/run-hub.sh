#!/bin/sh
# A vertex of very high degree (bench/README.md, "A hub no grid splits"):
# hpfc-pack of a hub of N spokes (bench/gen_hub.py), valid, then with one
# spoke overlapping another at the hub (refused): wall and CPU time, peak
# resident memory, exit status and the message.
#   sh bench/run-hub.sh [SPOKES ...]    default: 1e4 1e5
# Release build in build-bench/; the maps are generated once into
# build-bench/hubs/.
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
pack=build-bench/hpfc-pack/hpfc-pack
dir=build-bench/hubs
mkdir -p "$dir"
printf '%-7s %-8s %9s %9s %9s %5s  %s\n' spokes map wall_s cpu_s peak_MB exit message
for n in ${*:-1e4 1e5}; do
    [ -f "$dir/hub-$n.pfc" ] || python3 bench/gen_hub.py "$n" "$dir/hub-$n.pfc" 2>/dev/null
    [ -f "$dir/flaw-$n.pfc" ] || python3 bench/gen_hub.py "$n" "$dir/flaw-$n.pfc" --flaw 2>/dev/null
    for map in hub flaw; do
        rc=0
        /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$pack" -q --force "$dir/$map-$n.pfc" \
            -o "$dir/$map-$n.hpfc" 2>"$dir/err" || rc=$?
        read -r wall user sys kb <<EOT
$(tail -n 1 "$dir/time")
EOT
        printf '%-7s %-8s %9.2f %9.2f %9.1f %5s  %s\n' "$n" "$map" "$wall" \
            "$(python3 -c "print($user + $sys)")" "$(python3 -c "print($kb / 1024)")" "$rc" \
            "$(grep -v '^Command exited' "$dir/err" | head -c 120)"
        rm -f "$dir/$map-$n.hpfc"
    done
done
