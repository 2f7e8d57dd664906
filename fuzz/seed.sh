#!/usr/bin/env bash
# Fills fuzz/corpus/bvh_parse and fuzz/corpus/import with seeds: every fixture cut to its first 2 frames (so that inputs stay
# small and libFuzzer's max_len stays near the size of a real header) and every malformed file.
set -euo pipefail
cd "$(dirname "$0")/.."
out=fuzz/corpus/bvh_parse
mkdir -p "$out"
for f in tests/fixtures/*/*.bvh; do
  awk 'BEGIN{m=0} /^MOTION/{m=1} m==1 && /^Frames:/{print "Frames: 2"; next} {print} m==1 && ++n>=4{exit}' "$f" \
    > "$out/fixture_$(basename "$f")"
done
cp tests/malformed/*.bvh "$out/"
echo "seeded $(ls "$out" | wc -l) files into $out"

# The whole import: every fixture (the rig families too) cut to 4 frames, and one with a manual map.
imp=fuzz/corpus/import
mkdir -p "$imp"
for f in tests/fixtures/*/*.bvh; do
  awk 'BEGIN{m=0} /^MOTION/{m=1} m==1 && /^Frames:/{print "Frames: 4"; next} {print} m==1 && ++n>=6{exit}' "$f" \
    > "$imp/fixture_$(basename "$f")"
done
{ echo '{"Hips": "Hips", "Head": null}'; cat "$imp/fixture_m21_walk.bvh"; } > "$imp/map_m21_walk.bvh"
echo "seeded $(ls "$imp" | wc -l) files into $imp"
