#!/usr/bin/env bash
# Regenerates problems/push/paper10: ten pushing shelves as Papallas & Dogar (2020,
# Section VI-B) describe theirs (`cluttertamp generate --push`): a 0.59 x 0.584 x 0.26 m
# shelf, the target at the back, ten obstacles of radius 3 cm and 10 cm tall; each
# problem reaches the target with the UR10's arm on a planar base, the paper's controls
# and goal. Each gets its automatic guidance (pNN-guidance.yaml, `cluttertamp guide
# --auto`: one guide), which a person may edit.
# Usage: scripts/make-paper-push-scenes.sh [BUILD_DIR]   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/bin/cluttertamp"
dir=problems/push/paper10
mkdir -p "$dir"
for seed in 1 2 3 4 5 6 7 8 9 10; do
  n=$(printf "p%02d" "$seed")
  "$bin" generate --push --seed "$seed" --quiet --output "$dir/$n-scene.yaml" --problem "$dir/$n.yaml"
  sed -i "s/^name: $n\$/name: paper10-$n/" "$dir/$n.yaml"
  "$bin" guide "$dir/$n.yaml" --auto --output "$dir/$n-guidance.yaml" --quiet
done
echo "wrote $dir: ten problems, scenes and guidance files"
