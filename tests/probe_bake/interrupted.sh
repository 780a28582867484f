#!/bin/sh
# interrupted.sh BAKE SCENE DATA FILE: a copy of FILE (an existing cloud) in a folder of its own
# must survive a bake of SCENE onto it that is interrupted (SIGINT after 1 s) byte for byte, and
# that folder must gain no file. The folder is private so that other tests writing next to FILE
# at the same time (ctest -j) cannot change its listing.
set -u
bake=$1 scene=$2 data=$3 file=$4
dir=$(dirname "$file")/interrupted.$$
rm -rf "$dir" && mkdir -p "$dir" || exit 1
target=$dir/cloud.pcld
cp "$file" "$target" || exit 1
cp "$file" "$dir.keep" || exit 1
before=$(ls -a "$dir")
timeout -s INT 1 "$bake" "$scene" -o "$target" --data "$data" --spacing 2 >/dev/null 2>&1
rc=$?
after=$(ls -a "$dir")
status=0
[ "$rc" -eq 124 ] || { echo "the bake was not interrupted (exit $rc)"; status=1; }
cmp "$target" "$dir.keep" || { echo "the old file changed"; status=1; }
[ "$before" = "$after" ] || { echo "files appeared or vanished:"; echo "$before" > "$dir.b"; echo "$after" | diff "$dir.b" -; rm -f "$dir.b"; status=1; }
rm -rf "$dir" "$dir.keep"
[ "$status" -eq 0 ] && echo "old file intact after an interrupted bake"
exit "$status"
