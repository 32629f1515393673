"""Drop mujoco-rs's accessors for the mjModel / mjData fields a MuJoCo version no longer has.

mujoco-rs's wrappers name every field of mjModel and mjData in macro tables. After its FFI is
regenerated from another MuJoCo's headers (scripts/mujoco.sh), the fields that version removed are
found by comparing the two FFI files' structs, and each wrapper line that declares one is removed
(and the name dropped from the size lists). Fields a version adds get no accessor: envc reads
none of them.

usage: mujoco_rs_fields.py OLD_FFI NEW_FFI CRATE_DIR
"""

import re
import sys
from pathlib import Path


def struct_fields(ffi: str, name: str) -> set[str]:
    body = re.search(r"pub struct " + name + r" \{(.*?)\n\}", ffi, re.S)
    if body is None:
        sys.exit(f"mujoco_rs_fields: no struct {name} in the FFI")
    return set(re.findall(r"^\s*pub(?:\(crate\))? (\w+):", body.group(1), re.M))


def main() -> None:
    old, new, crate = (Path(a) for a in sys.argv[1:4])
    old_ffi, new_ffi = old.read_text(), new.read_text()
    for struct, wrapper in (("mjModel_", "mj_model.rs"), ("mjData_", "mj_data.rs")):
        gone = struct_fields(old_ffi, struct) - struct_fields(new_ffi, struct)
        path = crate / "src" / "wrappers" / wrapper
        lines = path.read_text().split("\n")
        kept = []
        for line in lines:
            declared = re.match(r"\s*(?:\(mut = unsafe\) |\[ffi\] )?(\w+):", line)
            if declared and declared.group(1) in gone:
                continue
            for field in gone:
                line = re.sub(r"\b" + field + r",\s*", "", line)
            kept.append(line)
        path.write_text("\n".join(kept))
        print(f"mujoco_rs_fields: {struct}: {len(gone)} fields gone: {' '.join(sorted(gone))}")


if __name__ == "__main__":
    main()
