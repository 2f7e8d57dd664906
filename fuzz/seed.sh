#!/usr/bin/env bash
# Fills fuzz/corpus/bvh_parse with seeds: every fixture cut to its first 2 frames (so that inputs stay
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
