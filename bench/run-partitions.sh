#!/bin/sh
# A build in parts (issue 32; bench/README.md, "A build in parts"):
# hpfc-pack of generated street networks (bench/gen_streets.py) whole and
# with --partitions 4 and 16, each run's wall and CPU time and peak
# resident memory (GNU time), and the files compared byte for byte.
#   sh bench/run-partitions.sh [POINTS ...]    default: 1e6 1e7
# Release build in build-bench/; the networks are generated once into
# build-bench/streets/.
set -eu
cd "$(dirname "$0")/.."
[ -d build-bench ] || meson setup build-bench --buildtype=release -Dtests=true >/dev/null
ninja -C build-bench hpfc-pack/hpfc-pack >/dev/null
pack=build-bench/hpfc-pack/hpfc-pack
dir=build-bench/streets
mkdir -p "$dir"
sizes=${*:-1e6 1e7}
printf '%-8s %10s %6s %9s %9s %10s %8s  %s\n' points parts "" wall_s cpu_s peak_MB "MB/Mpt" bytes
for n in $sizes; do
    pfc=$dir/streets-$n.pfc
    [ -f "$pfc" ] || python3 bench/gen_streets.py "$n" "$pfc"
    points=$(python3 -c "print(int(float('$n')))")
    for k in 1 4 16; do
        out=$dir/streets-$n-$k.hpfc
        /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$pack" -q --force --partitions "$k" "$pfc" -o "$out"
        read -r wall user sys kb <"$dir/time"
        same=same
        [ "$k" = 1 ] || cmp -s "$dir/streets-$n-1.hpfc" "$out" || same=DIFFERENT
        python3 -c "
w, u, s, kb, pts = $wall, $user, $sys, $kb, $points
print('%-8s %10s %6s %9.2f %9.2f %10.1f %8.1f  %s' % ('$n', '$k', '', w, u + s, kb / 1024, kb / 1024 / (pts / 1e6), '$same'))"
    done
    rm -f "$dir"/streets-"$n"-4.hpfc "$dir"/streets-"$n"-16.hpfc
done
