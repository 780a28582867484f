#!/bin/sh
# interrupted.sh BAKE SCENE DATA FILE: FILE (an existing cloud) must survive a bake of SCENE onto
# it that is interrupted (SIGINT after 1 s) byte for byte, and its folder must gain no file.
set -u
bake=$1 scene=$2 data=$3 file=$4
dir=$(dirname "$file")
cp "$file" "$file.keep" || exit 1
before=$(ls -a "$dir")
timeout -s INT 1 "$bake" "$scene" -o "$file" --data "$data" --spacing 2 >/dev/null 2>&1
rc=$?
after=$(ls -a "$dir")
status=0
[ "$rc" -eq 124 ] || { echo "the bake was not interrupted (exit $rc)"; status=1; }
cmp "$file" "$file.keep" || { echo "the old file changed"; status=1; }
[ "$before" = "$after" ] || { echo "files appeared or vanished:"; echo "$before" > "$file.b"; echo "$after" | diff "$file.b" -; rm -f "$file.b"; status=1; }
rm -f "$file.keep"
[ "$status" -eq 0 ] && echo "old file intact after an interrupted bake"
exit "$status"
