# Sourced by tests/wheel/run.sh and tests/wheel/crate.sh (ROOT and WORK set).
# Runs a command with the checkout replaced by an empty directory, from WORK, with none of the
# variables that could point back at it.
# Where a private mount namespace cannot be made (no CAP_SYS_ADMIN), a user namespace is tried;
# without either, the checkout stays visible and the run says so.
UNSHARE=(unshare -m --propagation private)
if ! "${UNSHARE[@]}" true 2>/dev/null; then
  UNSHARE=(unshare -rm --propagation private)
  "${UNSHARE[@]}" true 2>/dev/null || UNSHARE=()
fi
hidden() {
  local cmd="cd '$WORK' && $*"
  if [ ${#UNSHARE[@]} -gt 0 ]; then
    cmd="mount -t tmpfs -o size=1m envc-hidden '$ROOT' && $cmd"
  else
    echo "envc test: cannot make a mount namespace here; the checkout stays visible" >&2
  fi
  env -u MUJOCO_DYNAMIC_LINK_DIR -u MUJOCO_INCLUDE_DIR -u LD_LIBRARY_PATH -u PYTHONPATH \
    -u VIRTUAL_ENV -u ENVC_SPEC_PATH "${UNSHARE[@]}" bash -c "$cmd"
}
