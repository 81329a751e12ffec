#!/usr/bin/env bash
# Regenerates problems/push/shelf10: ten shelves like Papallas & Dogar's (2020, Section
# VI-B): the target at the back, ten movable cylinders (radius 3.5-4 cm, height
# 24-29 cm, 0.3 kg, friction 0.5) placed at random without overlap in a 0.55 m wide,
# 0.4 m deep cabinet. Each gets a reach problem (pNN.yaml) and its automatic guidance
# (pNN-guidance.yaml, `cluttertamp guide`: one guide), which a person may edit.
# Usage: scripts/make-push-scenes.sh [BUILD_DIR]   (after scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/bin/cluttertamp"
dir=problems/push/shelf10
mkdir -p "$dir"
for seed in 1 2 3 4 5 6 7 8 9 10; do
  n=$(printf "p%02d" "$seed")
  "$bin" generate --objects 11 --width 0.55 --depth 0.4 --seed "$seed" --any --quiet --output "$dir/$n-scene.yaml"
  cat > "$dir/$n.yaml" <<PROBLEM
# Reaching through clutter (Papallas & Dogar 2020), shelf $seed of ten: reach the target
# at the back by pushing. Planned here by kinodynamic RRT; \`cluttertamp bench push\`
# also runs KPIECE1 and guided planning (grtc with $n-guidance.yaml) on it.
# Made by scripts/make-push-scenes.sh. Format: docs/file-formats.md, "Problem files".
version: 1
name: shelf10-$n
scene: $n-scene.yaml
robot: {description: ../../../domains/robots/ur10_ag95.yaml}
task: {reach: target}
planner:
  plugin: rtc_ompl
  time_limit: 300
  seed: 0
  parameters: {planner: rrt, max_propagations: 20000}  # work budget; time_limit is the outer limit
PROBLEM
  "$bin" guide "$dir/$n.yaml" --auto --output "$dir/$n-guidance.yaml" --quiet
done
echo "wrote $dir: ten problems, scenes and guidance files"
