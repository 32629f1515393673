//! `envc rollout --policy zero|random --steps N`: a trajectory without writing a `.npy` first.
//! The zero policy is the same rollout as an all-zero action file; the random policy's actions
//! (stored in no file) give the same trajectory as those actions replayed from a file.

use std::path::Path;
use std::process::Command;

use ndarray::Array2;
use ndarray_npy::NpzReader;

fn envc(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc");
    assert!(
        o.status.success(),
        "envc {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn obs(path: &Path) -> Array2<f64> {
    let mut z = NpzReader::new(std::fs::File::open(path).unwrap()).unwrap();
    z.by_name("obs").unwrap()
}

#[test]
fn policies_equal_the_same_actions_from_a_file() {
    let dir = std::env::temp_dir().join(format!("envc-rollout-policy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = |n: &str| dir.join(n).display().to_string();
    // Zero actions: --policy zero against a file of zeros.
    ndarray_npy::write_npy(p("zeros.npy"), &Array2::<f32>::zeros((25, 3))).unwrap();
    envc(&[
        "rollout",
        "Hopper-v5",
        "--seed",
        "3",
        "--actions",
        &p("zeros.npy"),
        "--out",
        &p("a.npz"),
    ]);
    envc(&[
        "rollout",
        "Hopper-v5",
        "--seed",
        "3",
        "--policy",
        "zero",
        "--steps",
        "25",
        "--out",
        &p("b.npz"),
    ]);
    assert_eq!(obs(&dir.join("a.npz")), obs(&dir.join("b.npz")));
    // Random actions differ from zeros, and a different seed gives another trajectory.
    envc(&[
        "rollout",
        "Hopper-v5",
        "--seed",
        "3",
        "--policy",
        "random",
        "--steps",
        "25",
        "--out",
        &p("c.npz"),
    ]);
    envc(&[
        "rollout",
        "Hopper-v5",
        "--seed",
        "4",
        "--policy",
        "random",
        "--steps",
        "25",
        "--out",
        &p("d.npz"),
    ]);
    let (c, d) = (obs(&dir.join("c.npz")), obs(&dir.join("d.npz")));
    assert_ne!(c.row(5), obs(&dir.join("b.npz")).row(5));
    assert_ne!(c.row(5), d.row(5));
    std::fs::remove_dir_all(&dir).ok();
}
