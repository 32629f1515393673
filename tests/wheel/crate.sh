#!/usr/bin/env bash
# A crate of one's own outside the checkout (scripts/test.sh runs this): `cargo new` plus
# `envc = { path = ... }`, built with plain `cargo build`, no environment variables and no copied
# config (MuJoCo through pkg-config, installed by scripts/setup.sh), its binary run from another
# directory with the checkout hidden (tests/wheel/hidden.sh); its zero-action episode must be the
# reference's.
# Usage: tests/wheel/crate.sh WORKDIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
WORK="${1:?usage: tests/wheel/crate.sh WORKDIR}"
mkdir -p "$WORK"
WORK="$(cd "$WORK" && pwd)"
case "$WORK" in "$ROOT"/*) echo "crate test: WORKDIR must be outside the checkout" >&2; exit 1 ;; esac
# shellcheck source=tests/wheel/hidden.sh
source "$ROOT/tests/wheel/hidden.sh"

CRATE="${XDG_CACHE_HOME:-$HOME/.cache}/envc-tests/mybot"
mkdir -p "$CRATE/src"
cat > "$CRATE/Cargo.toml" <<EOF
[package]
name = "mybot"
version = "0.1.0"
edition = "2024"

[dependencies]
envc = { path = "$ROOT/runtime" }
EOF
cat > "$CRATE/src/main.rs" <<'EOF'
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut env = envc::Env::make("Hopper-v5", &[])?;
    env.reset(Some(0));
    let (mut n, mut ret) = (0, 0.0);
    loop {
        let s = env.step(&[0.0; 3])?;
        n += 1;
        ret += s.reward;
        if s.terminated || s.truncated {
            break;
        }
    }
    println!("Hopper-v5: one episode with zero actions, {n} steps, return {ret:.3}");
    Ok(())
}
EOF
# Its dependencies build into the checkout's target/outside/, kept between runs and shared with
# scripts/test.sh's `envc new` crate (whose template optimizes its dependencies: separate builds).
OUTSIDE="$ROOT/target/outside"
(cd "$CRATE" && env -u MUJOCO_DYNAMIC_LINK_DIR -u MUJOCO_INCLUDE_DIR -u PKG_CONFIG_PATH \
  CARGO_TARGET_DIR="$OUTSIDE" cargo build -q)
cp "$OUTSIDE/debug/mybot" "$WORK/mybot-bin"
got="$(hidden "'$WORK/mybot-bin'")"
want="$("$ROOT/.venv/bin/python" "$ROOT/tests/reference/zero_action_episode.py")"
[ "$got" = "$want" ] || { echo "hand-made crate: got '$got', the reference gives '$want'" >&2; exit 1; }
echo "hand-made crate: plain cargo build, run with the checkout hidden: $got (as the reference)"
