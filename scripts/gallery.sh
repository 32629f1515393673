#!/usr/bin/env bash
# The README's gallery: one picture per bundled v5 env, the Go1, a maze and a MaMuJoCo split,
# rendered headless by `envc render` (zero policy, seed 0, the frame after 10 steps) into
# docs/gallery/*.png. `scripts/gallery.sh --check` re-renders into a temporary directory and
# fails if any committed picture differs, so the gallery cannot go stale silently.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
CHECK=0
[ "${1:-}" = "--check" ] && CHECK=1
cargo build -q --release -p envc-cli
ENVC="$ROOT/target/release/envc"
OUT="$ROOT/docs/gallery"
[ $CHECK = 1 ] && OUT="$(mktemp -d)"
mkdir -p "$OUT"
IDS=(Ant-v5 HalfCheetah-v5 Hopper-v5 Humanoid-v5 HumanoidStandup-v5 InvertedDoublePendulum-v5
     InvertedPendulum-v5 Pusher-v5 Reacher-v5 Swimmer-v5 Walker2d-v5
     specs/examples/go1.toml AntMaze_UMaze-v5 MaMuJoCo-Ant-v1)
# The Go1's model is not bundled (Menagerie); GO1_XML points at a copy (default: the shared one).
GO1_XML="${GO1_XML:-$ROOT/../shared/models/unitree_go1/scene.xml}"
for id in "${IDS[@]}"; do
  name="$(basename "$id" .toml)"
  frames="$(mktemp -d)"
  set_args=()
  [ "$name" = go1 ] && set_args=(--set "xml_file=$GO1_XML")
  "$ENVC" render "$id" "${set_args[@]}" --policy zero --seed 0 --episodes 1 --max-steps 10 --size 320x240 --out "$frames/" >/dev/null
  last="$(ls "$frames" | sort | tail -n 1)"
  cp "$frames/$last" "$OUT/$name.png"
  rm -rf "$frames"
done
if [ $CHECK = 1 ]; then
  status=0
  for f in "$OUT"/*.png; do
    if ! cmp -s "$f" "docs/gallery/$(basename "$f")"; then
      echo "gallery: docs/gallery/$(basename "$f") is stale (re-run scripts/gallery.sh)" >&2
      status=1
    fi
  done
  rm -rf "$OUT"
  exit $status
fi
echo "gallery: ${#IDS[@]} pictures in docs/gallery/"
