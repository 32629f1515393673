#!/usr/bin/env bash
# envc's test suite, runnable on a fresh machine (it runs scripts/setup.sh first):
#   1. hygiene: the size rules (scripts/sizes.py), no import circle (scripts/import_circles.py), cargo fmt --check, clippy and rustdoc with warnings denied, ruff and mypy --strict on the Python package (its stubs, by mypy's stubtest, in the checks lane below);
#   2. the compiled models in assets/ are identical to the reference's (tests/reference/check_models.py),
#      and the installed reference still gives the published golden values (record.py --verify-golden);
#   3. the Rust tests (a few binaries: `cargo test --workspace`), including the parity replay of the committed fixtures under the numerics
#      profile each was recorded with (so they pass on every CPU);
#   4. the dispatch matrix: the reference's CPU-dependent primitives (OpenBLAS ddot under every
#      OPENBLAS_CORETYPE this CPU runs, numpy's exp with and without X86_V4) recorded live, and
#      envc's `auto` must pick the same profile and give the same bits; `envc rollout` checked
#      against the reference under several of those settings;
#   5. the Python package's tests (tests/python, pytest) against the live reference;
#   6. live cross-checks: the Python reference records fresh trajectories under a new random seed
#      and envc must reproduce them bit for bit. Set ENVC_LIVE_SEED to repeat a run.
# The set-up's release builds run beside the hygiene checks. Then the Python package's checks and
# the crates outside the repository run in lanes of their own beside the Rust tests, and after
# those the rest in two more lanes; lines are marked [setup], [python], [new], [rust], [checks]
# and [live].
# The reference and envc both read OPENBLAS_CORETYPE and NPY_*_CPU_FEATURES from the environment,
# so every check holds for whatever this machine (or its environment) makes numpy compute.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PY="$ROOT/.venv/bin/python"
# Each check that passes is counted (in a file: the lanes below are processes of their own),
# with the suite's elapsed time; `set -e` stops at the first that fails.
LIVE="$(mktemp -d)"
PASSED="$(mktemp)"
trap 'rm -rf "$LIVE" "$PASSED"' EXIT
passed() { echo "$1" >> "$PASSED"; echo "test.sh: check $(wc -l < "$PASSED") passed, ${SECONDS}s: $1"; }
# Job control: every background job below is a process group of its own, so a failure stops the
# others at once.
set -m
JOBS=()
fail() {
  kill -- "${JOBS[@]/#/-}" 2>/dev/null || true
  wait || true
  echo "test.sh: $(wc -l < "$PASSED") passed, 1 failed (the job whose last lines are above)" >&2
  exit "$1"
}

# What cargo needs (the toolchain, system packages, MuJoCo); the rest of the set-up (the reference's
# venv, the Python package's release build) runs beside the hygiene checks below, and then the
# wheel (scripts/build-wheel.sh: the extension again, and built for MuJoCo 4.0.1) and the release
# CLI (pytest's and the checks' `envc`). With workspace-hack's unified features the CLI compiles
# only its own crates on top of the extension's build.
bash scripts/setup.sh --mujoco
( { bash scripts/setup.sh && scripts/build-wheel.sh "$LIVE/dist" | tail -1 &&
    cargo build -q --release --locked -p envc-cli --features hdf5-static; } 2>&1 | sed -u 's/^/[setup] /' ) &
SETUP="$!"
JOBS+=("$SETUP")

# Hygiene first (it fails fastest): formatted, no clippy warnings (workspace lints in Cargo.toml), docs build without warnings.
# (Chained: `set -e` does not reach inside a function called with `||`.)
hygiene() {
  python3 scripts/sizes.py &&
    python3 scripts/import_circles.py &&
    cargo fmt --all --check &&
    cargo clippy -q --workspace --all-targets -- -D warnings &&
    RUSTDOCFLAGS="-D warnings" cargo doc -q --workspace --no-deps
}
status=0
hygiene || status=$?
[ "$status" = 0 ] || fail "$status"
# The Rust tests' build while the set-up finishes (running them needs its venv).
( cargo test -q --workspace --no-run 2>&1 | sed -u 's/^/[rust] /' ) &
BUILD="$!"
JOBS+=("$BUILD")
status=0
wait "$SETUP" || status=$?
[ "$status" = 0 ] || fail "$status"
# Specs whose model lies in an installed Python package (`${python:gymnasium_robotics}`, the
# Kitchen's) find it on the venv's search path, in every check below, as `import envc` there does.
ENVC_PYTHON_PATH="$("$PY" -c 'import os, sys; print(os.pathsep.join(p for p in sys.path if p))')"
export ENVC_PYTHON_PATH
# The extension's and the CLI's release builds ask for shared dependencies alike, so the second
# reuses the first's (workspace-hack/Cargo.toml).
"$PY" scripts/release_features.py
# The Python package: ruff, and mypy --strict with the native core typed by its stub (the venv's
# pinned tools, so after the set-up).
scripts/python-lint.sh
passed "hygiene (sizes, import circles, fmt, clippy, rustdoc, release features, ruff, mypy --strict)"
SEED="${ENVC_LIVE_SEED:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}"
echo "pytest and the live checks below: seed $SEED (ENVC_LIVE_SEED=$SEED repeats them)"

# The rest in four lanes: the Python package's checks, the Rust-side checks, the crates outside the
# repository, and the live checks against the reference. The checks are independent of each other but for the order inside
# a lane (Ray runs in the Python lane only: pytest's clusters and the wheel's would find each other;
# the MaMuJoCo reference, used by pytest and the live lane, builds under a lock:
# tests/reference/record_mamujoco.py).
# Each lane's lines carry its name.
lane_python() {
  # The wheel's venv of its pinned dependencies (a minute of pip) is made while pytest runs.
  tests/wheel/run.sh --prebuilt "$LIVE/dist" --venv-only "$LIVE/wheel" > "$LIVE/wheel-venv.log" 2>&1 &
  local venv="$!"
  # The envc Python package (installed by setup.sh) against the live reference: Gymnasium's classes,
  # vector envs, mazes and PettingZoo, same seeds and actions, fresh seeds every run.
  # Its fresh cases draw from the run's one seed, as the live checks below do.
  # In two processes (pytest runs one test at a time): the tests that start Ray clusters and the GPU
  # executor's, then the wheel (whose Ray cluster must not meet pytest's), beside the rest.
  local ray=(tests/python/test_ray.py tests/python/test_dataset_suite.py tests/python/test_gpu.py)
  local pytest=("$PY" -m pytest -q -p no:cacheprovider --durations=5)
  ENVC_LIVE_SEED="$SEED" "${pytest[@]}" --basetemp "$LIVE/pytest-rest" "${ray[@]/#/--ignore=}" \
    tests/python > "$LIVE/pytest-rest.log" 2>&1 &
  local rest="$!"
  ENVC_LIVE_SEED="$SEED" "${pytest[@]}" --basetemp "$LIVE/pytest-ray" "${ray[@]}"

  # The wheel of scripts/build-wheel.sh outside its checkout, in a venv of its pinned dependencies,
  # run with the checkout hidden (tests/wheel/run.sh).
  wait "$venv" || { cat "$LIVE/wheel-venv.log"; exit 1; }
  tests/wheel/run.sh --prebuilt "$LIVE/dist" "$LIVE/wheel"
  passed "wheel"
  local status=0
  wait "$rest" || status=$?
  cat "$LIVE/pytest-rest.log"
  [ "$status" = 0 ] || exit "$status"
  passed "pytest"
}

lane_checks() {
  # The native core's type stubs (python/envc/_envc.pyi) against the extension setup.sh built
  # (here rather than before pytest, which is the longest lane).
  scripts/stubtest.sh
  passed "stubs (mypy stubtest)"
  "$PY" tests/reference/check_models.py
  passed "compiled models"
  # The golden values were published from an AVX-512 Xeon; a forced SSE kernel (OPENBLAS_CORETYPE=Prescott)
  # changes Pusher's last bits, so they are checked under the CPU's own OpenBLAS kernel.
  env -u OPENBLAS_CORETYPE "$PY" tests/reference/record.py --verify-golden
  passed "golden values"

  # The fuzzer's bounded pass, every target: 30 s here (ENVC_FUZZ_SECONDS; a plain `cargo test`
  # takes 60). Its seed is fixed, so a pass repeats the same inputs: longer runs are
  # docs/fuzzing.md's, with other seeds.
  ENVC_FUZZ_SECONDS="${ENVC_FUZZ_SECONDS:-30}" cargo test -q --workspace --test cli fuzz::
  passed "fuzz"

  # The catalogue and the fuzzer's `envc` targets again against the optimized binary: undefined
  # behaviour that only the optimizer exposes (an error unwinding through a `C` declaration) shows
  # only there.
  ENVC_BIN="$ROOT/target/release/envc" cargo test -q --workspace --test cli catalogue::
  ENVC_BIN="$ROOT/target/release/envc" ENVC_FUZZ_TARGETS=compile,cli ENVC_FUZZ_SECONDS=15 \
    cargo test -q --workspace --test cli fuzz::
  passed "release catalogue and fuzz"

  # Rendering: tests/python/test_render.py above compares frames with Gymnasium's; here the
  # README's gallery is re-rendered and must equal the committed pictures.
  scripts/gallery.sh --check
  passed "gallery"

  # The dispatch matrix (see 4. above).
  "$PY" tests/reference/record_numerics.py --matrix "$LIVE/numerics" --quick
  ENVC_NUMERICS_DIR="$LIVE/numerics" cargo test -q --workspace --test integration numerics::
  passed "numerics dispatch matrix"
}

# Crates outside the repository, in a lane of their own from the start: on a fresh machine their
# dependencies (builds of their own, as a user's crate gets) take minutes.
lane_new() {
  # A crate of one's own made by `envc new` (with the release CLI built above): builds and runs
  # with plain `cargo run` (no environment variables, nothing copied by hand), and its typed env's
  # zero-action episode is the reference's (steps and return).
  target/release/envc new "$LIVE/newbot" --spec Hopper-v5 >/dev/null
  # (target/outside/: tests/wheel/crate.sh's hand-made crate builds there too, plain, while this
  # template optimizes its dependencies, so the two share the directory, not the builds.)
  got="$(cd "$LIVE/newbot" && env -u MUJOCO_DYNAMIC_LINK_DIR -u MUJOCO_INCLUDE_DIR -u PKG_CONFIG_PATH \
    CARGO_TARGET_DIR="$ROOT/target/outside" cargo run -q)"
  want="$("$PY" "$ROOT/tests/reference/zero_action_episode.py")"
  [ "$got" = "$want" ] || { echo "envc new: got '$got', the reference gives '$want'" >&2; exit 1; }
  echo "envc new: $got (as the reference)"
  passed "envc new"
  # A hand-made crate (`envc = { path = ... }`, plain `cargo build`), run with the checkout hidden.
  tests/wheel/crate.sh "$LIVE/crate"
  passed "hand-made crate"
}

lane_live() {
  # `envc rollout` checked against the reference from outside, as any other tool would (fresh seeds):
  # in this machine's environment, then with OpenBLAS forced to another kernel and numpy's AVX-512
  # loops off, where the CPU can run them (suite, mazes, MaMuJoCo, and Minari datasets written by
  # `envc collect` and replayed by the real minari).
  # (target/debug/envc: built by `cargo test --workspace` above. Every later cargo command selects
  # the whole workspace too, so features unify as they did there and nothing is rebuilt.)
  "$PY" tests/reference/check_rollout.py --envc target/debug/envc
  passed "envc rollout, live"
  # (`-u OPENBLAS_CORETYPE`: the CPU's own choice, whatever this environment forces.) Under the CPU's
  # own kernel every check runs; under each forced one the suite's rollouts and one of the other
  # three checks, turn by turn with the run's seed, so that each forced kernel meets all of them
  # within three runs.
  local others=(check_maze_rollout check_mamujoco_rollout check_minari) turn="$SEED"
  for setting in "-u OPENBLAS_CORETYPE" "OPENBLAS_CORETYPE=Prescott" \
                 "OPENBLAS_CORETYPE=Haswell NPY_DISABLE_CPU_FEATURES=X86_V4" "OPENBLAS_CORETYPE=SkylakeX"; do
    if "$PY" tests/reference/numerics_profile.py --can-run $setting; then
      echo "live checks under env $setting"
      # (With no OPENBLAS_CORETYPE in this environment, the first check of the lane was this one.)
      if [ "$setting" != "-u OPENBLAS_CORETYPE" ] || [ -n "${OPENBLAS_CORETYPE:-}" ]; then
        env $setting "$PY" tests/reference/check_rollout.py --envc target/debug/envc
      fi
      local checks=("${others[@]}")
      [ "$setting" = "-u OPENBLAS_CORETYPE" ] || { checks=("${others[$((turn % 3))]}"); turn=$((turn + 1)); }
      for check in "${checks[@]}"; do
        local args=(--envc target/debug/envc)
        [ "$check" = check_maze_rollout ] && args+=(--seed "$RANDOM")
        env $setting "$PY" "tests/reference/$check.py" "${args[@]}"
      done
      passed "live checks under $setting"
    fi
  done

  # Minari datasets written by envc, loaded, sampled and replayed by the real minari/Gymnasium (fresh
  # seed), an interrupted collection; then Python DataCollector datasets read back by envc.
  MINARI_PY="$(mktemp -d)"
  "$PY" tests/reference/check_minari.py --envc target/debug/envc --python-out "$MINARI_PY"
  passed "Minari datasets, live"
  ENVC_MINARI_DIR="$MINARI_PY" cargo test -q --workspace --test integration minari::
  passed "Python DataCollector datasets read by envc"
  rm -rf "$MINARI_PY"

  echo "live cross-check against the Python reference, seed $SEED (ENVC_LIVE_SEED=$SEED repeats it)"
  "$PY" tests/reference/record.py --out "$LIVE" --seed "$SEED" --quick --skip-golden
  ENVC_PARITY_DIR="$LIVE" cargo test -q --workspace --test integration parity::
  passed "parity, live seed"
  # The same for vector envs (Gymnasium's sync vector env, both autoreset modes).
  "$PY" tests/reference/record_vector.py --out "$LIVE/vector" --seed "$SEED"
  ENVC_VECTOR_DIR="$LIVE/vector" cargo test -q --workspace --test integration vector::
  passed "vector, live seed"
  # MaMuJoCo v1: fresh-seed multi-agent trajectories of every scenario, conf and k = 0, 1, 2 replayed
  # through envc's multi-agent envs, and `envc rollout` on the multi-agent specs checked from outside.
  "$PY" tests/reference/record_mamujoco.py --out "$LIVE/mamujoco" --seed "$SEED" --quick
  ENVC_MAMUJOCO_DIR="$LIVE/mamujoco" cargo test -q --workspace --test integration mamujoco::
  passed "MaMuJoCo, live seed"
  "$PY" tests/reference/check_mamujoco_rollout.py --envc target/debug/envc --seed "$SEED"
  passed "MaMuJoCo rollout, live seed"
  # Mazes (PointMaze_*-v3, AntMaze_*-v5, custom maps): fresh-seed trajectories of every registered id
  # replayed through envc's maze envs, and `envc rollout`'s dict observations checked from outside.
  "$PY" tests/reference/record_maze.py --out "$LIVE/maze" --seed "$SEED"
  ENVC_MAZE_DIR="$LIVE/maze" cargo test -q --workspace --test integration maze::
  passed "mazes, live seed"
  "$PY" tests/reference/check_maze_rollout.py --envc target/debug/envc --seed "$SEED"
  passed "maze rollout, live seed"
  # Goal-conditioned robotics (Fetch v4, all 8 ids; the Shadow Hand): fresh-seed rollouts and
  # batched compute_reward of the reference replayed through envc's manipulation specs.
  "$PY" tests/reference/record_robotics.py --out "$LIVE/robotics" --seed "$SEED"
  ENVC_ROBOTICS_DIR="$LIVE/robotics" cargo test -q --workspace --test integration -- fetch:: hand::
  passed "Fetch and Shadow Hand, live seed"
  # Adroit v1 (dense and sparse): fresh-seed rollouts of the reference through the 200-step
  # truncation, replayed through envc's specs.
  "$PY" tests/reference/record_adroit.py --out "$LIVE/adroit" --seed "$SEED"
  ENVC_ADROIT_DIR="$LIVE/adroit" cargo test -q --workspace --test integration adroit::
  passed "Adroit, live seed"
  # FrankaKitchen-v1: fresh-seed rollouts of the reference (its checklist at its threshold and at a
  # larger one), replayed through envc's spec.
  "$PY" tests/reference/record_kitchen.py --out "$LIVE" --seed "$SEED"
  ENVC_KITCHEN_DIR="$LIVE" cargo test -q --workspace --test integration kitchen::
  passed "Franka Kitchen, live seed"
  # Minari datasets of maze envs (dict observations, both formats) written by `envc collect`, loaded
  # by the real minari and replayed in Gymnasium-Robotics (fresh seed).
  MZ="$(mktemp -d)"
  for fmt in arrow hdf5; do
    target/debug/envc collect PointMaze_Medium_Diverse_GRDense-v3 --dataset-id "envc/pointmaze-$fmt-v0" \
      --episodes 3 --seed "$SEED" --format "$fmt" --root "$MZ" --set max_episode_steps=40 >/dev/null
    "$PY" tests/reference/check_maze_minari.py --root "$MZ" --dataset-id "envc/pointmaze-$fmt-v0" \
      --env-id PointMaze_Medium_Diverse_GRDense-v3 --max-episode-steps 40
    passed "maze dataset ($fmt)"
  done
  target/debug/envc collect AntMaze_UMaze-v5 --dataset-id envc/antmaze-v0 --episodes 2 --seed "$SEED" \
    --root "$MZ" --set max_episode_steps=15 >/dev/null
  "$PY" tests/reference/check_maze_minari.py --root "$MZ" --dataset-id envc/antmaze-v0 \
    --env-id AntMaze_UMaze-v5 --max-episode-steps 15
  passed "AntMaze dataset"
  rm -rf "$MZ"

}

# MuJoCo 4.0.1 (envc's feature `mujoco-4.0.1`, docs/mujoco-versions.md): the integration tests,
# with the suites recorded per version replayed from their committed 4.0.1 fixtures; then the live
# cross-checks against Gymnasium, Gymnasium-Robotics and MaMuJoCo running on 4.0.1 under the run's
# fresh seed; then the wheel beside MuJoCo 4.0.1.
lane_mujoco4() {
  local venv="$ROOT/.venv-mujoco-4.0.1" req="$ROOT/tests/reference/requirements-mujoco-4.0.1.txt"
  if ! cmp -s "$req" "$venv/.envc-requirements" 2>/dev/null; then
    [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$req"
    cp "$req" "$venv/.envc-requirements"
  fi
  local py="$venv/bin/python" out="$LIVE/mujoco-4.0.1"
  local run=(cargo test -q -p envc-tests --features mujoco-4.0.1 --test integration --)
  # Every integration test but those that replay 3.17.0's own recordings (Fetch's and the Shadow
  # Hand's and the Kitchen's committed fixtures, the golden values, the AVX2-profile recordings, Python-made Minari
  # datasets, mjlab's term values, sensor values) or need 3.17.0's fixed arena (4.0.1 does not
  # overflow a `<size memory>` arena on Hopper): the suites recorded per version replay 4.0.1's.
  local only_317=(fetch::fetch_reach fetch::fetch_push fetch::fetch_slide fetch::fetch_pick_and_place
    hand::hand_reach hand::hand_manipulate_block hand::hand_manipulate_egg hand::hand_manipulate_pen
    hand::hand_manipulate_touch_sensors kitchen::kitchen_default kitchen::kitchen_checklist
    golden::golden_table_of_the_reference_doc
    parity::avx2_recording_is_bit_identical maze::maze_parity_avx2_recording
    mamujoco::mamujoco_parity_avx2_recording minari::reads_python_datacollector_datasets
    mjlab_terms::g1_terms_match_numpy_from_mjlabs_term_functions
    mjlab_terms::go1_terms_match_numpy_from_mjlabs_term_functions
    runtime_errors::a_model_mujoco_cannot_run_at_all_is_refused_when_the_env_is_built
    runtime_errors::a_mujoco_error_in_a_step_is_an_error_value_and_a_reset_recovers
    sensors::sensor_values_are_mujocos_by_name)
  "${run[@]}" --exact "${only_317[@]/#/--skip=}"
  passed "MuJoCo 4.0.1: the integration tests and the recorded suites"
  "$py" tests/reference/record.py --out "$out/parity" --seed "$SEED" --quick --skip-golden >/dev/null
  "$py" tests/reference/record_vector.py --out "$out/vector" --seed "$SEED" >/dev/null
  "$py" tests/reference/record_maze.py --out "$out/maze" --seed "$SEED" >/dev/null
  "$py" tests/reference/record_mamujoco.py --out "$out/mamujoco" --seed "$SEED" --quick >/dev/null
  "$py" tests/reference/record_robotics.py --out "$out/robotics" --seed "$SEED" >/dev/null
  "$py" tests/reference/record_adroit.py --out "$out/adroit" --seed "$SEED" >/dev/null
  "$py" tests/reference/record_kitchen.py --out "$out" --seed "$SEED" 2>/dev/null
  ENVC_PARITY_DIR="$out/parity" ENVC_VECTOR_DIR="$out/vector" ENVC_MAZE_DIR="$out/maze" \
    ENVC_MAMUJOCO_DIR="$out/mamujoco" ENVC_ROBOTICS_DIR="$out/robotics" ENVC_ADROIT_DIR="$out/adroit" \
    ENVC_KITCHEN_DIR="$out" \
    "${run[@]}" --exact parity::every_recorded_case_is_bit_identical \
    vector::replays_gymnasium_sync_vector_env_bit_for_bit maze::maze_parity mamujoco::mamujoco_parity \
    adroit::adroit_door adroit::adroit_hammer adroit::adroit_pen adroit::adroit_relocate \
    fetch::fetch_reach fetch::fetch_push fetch::fetch_slide fetch::fetch_pick_and_place \
    hand::hand_reach hand::hand_manipulate_block hand::hand_manipulate_egg \
    hand::hand_manipulate_pen hand::hand_manipulate_touch_sensors \
    kitchen::kitchen_default kitchen::kitchen_checklist
  passed "MuJoCo 4.0.1: live seed"
  tests/wheel/mujoco4.sh "$LIVE/dist" "$LIVE/wheel-mujoco-4.0.1"
  passed "MuJoCo 4.0.1: the wheel beside it"
}

# Each lane is a process group (`set -m` above), so a failing lane stops the others at once.
# The Python lane and the outside crates' lane start now; the Rust tests run beside them, and the
# two other lanes after them (they read target/debug/envc and the test binaries the Rust tests build). More lanes than
# cores: much of each lane is waiting (on a child process, a Ray cluster, the fuzzer's fixed
# minute), and with two lanes a quarter of the cores' time went idle.
( lane_python 2>&1 | sed -u 's/^/[python] /' ) &
LANES=("$!")
( lane_new 2>&1 | sed -u 's/^/[new] /' ) &
LANES+=("$!")
JOBS+=("${LANES[@]}")
status=0
wait "$BUILD" || status=$?
[ "$status" = 0 ] || fail "$status"
# The Rust tests, but for the fuzzer's bounded pass (a fixed budget of wall time): the checks lane
# runs it, rather than holding up everything after it.
status=0
( cargo test --workspace -- --skip fuzz::fuzz 2>&1 | sed -u 's/^/[rust] /' ) || status=$?
[ "$status" = 0 ] || fail "$status"
passed "Rust tests"
( lane_checks 2>&1 | sed -u 's/^/[checks] /' ) &
LANES+=("$!")
( lane_live 2>&1 | sed -u 's/^/[live] /' ) &
LANES+=("$!")
( lane_mujoco4 2>&1 | sed -u 's/^/[mujoco-4.0.1] /' ) &
LANES+=("$!")
JOBS+=("${LANES[@]: -3}")
while [ "${#LANES[@]}" -gt 0 ]; do
  status=0
  wait -n -p done_pid "${LANES[@]}" || status=$?
  [ "$status" = 0 ] || fail "$status"
  for i in "${!LANES[@]}"; do [ "${LANES[$i]}" = "$done_pid" ] && unset 'LANES[i]'; done
  LANES=("${LANES[@]}")
done

# A closing line in the plain "N passed, N failed" form, over the checks above.
echo "test.sh: $(wc -l < "$PASSED") passed, 0 failed"
