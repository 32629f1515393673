#!/usr/bin/env bash
# The README's gallery: one picture per bundled v5 env, the Go1, a maze and a MaMuJoCo split
# (its agents coloured),
# rendered headless by `envc render` (zero policy, seed 0, the frame after 10 steps) into
# docs/gallery/*.png. `scripts/gallery.sh --check` re-renders into a temporary directory and
# fails if any committed picture differs in more than 1 % of its pixels, so the gallery cannot go
# stale silently.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
CHECK=0
[ "${1:-}" = "--check" ] && CHECK=1
cargo build -q --release --locked -p envc-cli --features hdf5-static   # the build scripts/test.sh and the wheel use
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
  # The split itself is the picture: each agent's limbs in its own colour.
  case "$name" in MaMuJoCo-*) set_args=(--color-agents) ;; esac
  "$ENVC" render "$id" "${set_args[@]}" --policy zero --seed 0 --episodes 1 --max-steps 10 --size 320x240 --out "$frames/" >/dev/null
  last="$(ls "$frames" | sort | tail -n 1)"
  cp "$frames/$last" "$OUT/$name.png"
  rm -rf "$frames"
done
if [ $CHECK = 1 ]; then
  # Pixels, not bytes: Mesa's llvmpipe compiles its shaders for the CPU it runs on, so another CPU
  # (AVX2 rather than AVX-512) may round a few edge pixels differently. A stale picture (another
  # camera, model or pose) differs in far more than 1 % of its pixels.
  status=0
  "$ROOT/.venv/bin/python" - "$OUT" "$ROOT/docs/gallery" <<'PYEOF' || status=1
import sys, pathlib
import numpy as np
from PIL import Image
new_dir, old_dir = map(pathlib.Path, sys.argv[1:])
stale = 0
for f in sorted(new_dir.glob("*.png")):
    old = old_dir / f.name
    a = np.asarray(Image.open(f).convert("RGB"), dtype=np.int16)
    b = np.asarray(Image.open(old).convert("RGB"), dtype=np.int16) if old.exists() else None
    if b is None or a.shape != b.shape:
        print(f"gallery: docs/gallery/{f.name} is missing or of another size (re-run scripts/gallery.sh)", file=sys.stderr)
        stale += 1
        continue
    differ = (a != b).any(axis=2)
    share = differ.mean()
    if share > 0.01:
        print(f"gallery: docs/gallery/{f.name} is stale: {share:.1%} of its pixels differ, up to {np.abs(a - b).max()} (re-run scripts/gallery.sh)", file=sys.stderr)
        stale += 1
    elif differ.any():
        print(f"gallery: {f.name}: {differ.sum()} pixels differ (within the 1 % this CPU's rasteriser may round differently)")
sys.exit(1 if stale else 0)
PYEOF
  rm -rf "$OUT"
  exit $status
fi
echo "gallery: ${#IDS[@]} pictures in docs/gallery/"
