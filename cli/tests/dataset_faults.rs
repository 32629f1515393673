//! Datasets and output files under faults: concurrent collectors in different PID namespaces,
//! `kill -9` at seeded random points, an unwritable root, a full disk, a staging directory removed
//! under a running collection, nested dataset ids, and `rollout --out` over an existing file or
//! its own input. Afterwards nothing loadable-but-wrong may exist: a dataset is either absent or
//! complete (`envc dataset show` reads every episode and checks it against the metadata).
//! Mount and PID namespaces (`unshare`, root) stand in for containers sharing a datasets
//! directory, a read-only mount and a small disk; those tests print why and pass where `unshare`
//! is unavailable.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const ENVC: &str = env!("CARGO_BIN_EXE_envc");

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("envc-faults-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn envc(args: &[&str]) -> Output {
    Command::new(ENVC).args(args).output().expect("run envc")
}

/// `collect` arguments for `spec` into `root`.
fn collect_args<'a>(
    spec: &'a str,
    root: &'a str,
    id: &'a str,
    episodes: &'a str,
    format: &'a str,
) -> Vec<&'a str> {
    vec![
        "collect",
        spec,
        "--root",
        root,
        "--dataset-id",
        id,
        "--episodes",
        episodes,
        "--policy",
        "random",
        "--seed",
        "0",
        "--format",
        format,
    ]
}

fn spawn(args: &[&str]) -> Child {
    Command::new(ENVC)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn envc")
}

/// Whether `unshare` works here (it needs root or user namespaces).
fn unshare_works() -> bool {
    let ok = Command::new("unshare")
        .args(["-m", "--pid", "--fork", "--mount-proc", "true"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("skipped: `unshare -m --pid` is unavailable (needs root)");
    }
    ok
}

/// A shell command run in a new mount namespace (mounts vanish with it).
fn in_mount_ns(script: &str) -> Output {
    Command::new("unshare")
        .args(["-m", "sh", "-c", script])
        .env("ENVC", ENVC)
        .output()
        .expect("run unshare")
}

/// The lock files of running or dead collections under `root`.
fn locks(root: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(root.join(".envc-staging"))
        .map(|d| {
            d.flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "lock"))
                .collect()
        })
        .unwrap_or_default()
}

/// The staging directories under `root`.
fn staging_dirs(root: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(root.join(".envc-staging"))
        .map(|d| {
            d.flatten()
                .map(|e| e.path())
                .filter(|p| p.is_dir())
                .collect()
        })
        .unwrap_or_default()
}

fn wait_for_staging(root: &Path, child: &mut Child) {
    let t0 = Instant::now();
    while staging_dirs(root).is_empty() {
        if let Ok(Some(s)) = child.try_wait() {
            panic!("collect ended ({s}) before staging anything");
        }
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "no staging appeared"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Every dataset under `root` (a directory with `data/metadata.json`, hidden ones included) reads
/// back complete; returns their ids.
fn assert_nothing_wrong(root: &Path) -> Vec<String> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if !p.is_dir() {
                continue;
            }
            if p.join("data").join("metadata.json").is_file() {
                let o = envc(&["dataset", "show", p.to_str().unwrap()]);
                assert_eq!(
                    o.status.code(),
                    Some(0),
                    "{} loads but is wrong: {}",
                    p.display(),
                    text(&o.stderr)
                );
                out.push(p.strip_prefix(root).unwrap().display().to_string());
            } else {
                walk(&p, root, out);
            }
        }
    }
    let mut out = vec![];
    walk(root, root, &mut out);
    out.sort();
    out
}

/// One line on stderr, with the code, no Rust debug output.
fn assert_one_clean_line(stderr: &str, code: &str) {
    let lines: Vec<_> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "expected one line:\n{stderr}");
    assert!(lines[0].contains(&format!("error[{code}]")), "{stderr}");
    for noise in ["Os {", "Io(", "kind:", "ZipWriter", "panicked"] {
        assert!(!stderr.contains(noise), "debug output: {stderr}");
    }
}

#[test]
fn two_collectors_in_two_pid_namespaces_both_publish_complete_datasets() {
    if !unshare_works() {
        return;
    }
    let root = tmp("pidns");
    let r = root.to_str().unwrap();
    // The first runs as pid 2 of its namespace (the shell is pid 1): a pid the second collector,
    // in a namespace of its own, does not see. A pid check takes its staging for an orphan.
    let long = collect_args("Hopper-v5", r, "ns/long-v0", "400", "arrow").join(" ");
    let mut a = Command::new("unshare")
        .args(["--pid", "--fork", "--mount-proc", "sh", "-c"])
        .arg(format!("\"$ENVC\" {long}; exit $?"))
        .env("ENVC", ENVC)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_staging(&root, &mut a);
    // The second runs as pid 1 of its own namespace, so the first one's pid 2 is not there.
    let b = Command::new("unshare")
        .args(["--pid", "--fork", "--mount-proc", ENVC])
        .args(collect_args(
            "InvertedPendulum-v5",
            r,
            "ns/short-v0",
            "3",
            "hdf5",
        ))
        .output()
        .unwrap();
    assert!(b.status.success(), "{}", text(&b.stderr));
    assert!(
        a.try_wait().unwrap().is_none(),
        "the first collection ended before the second ran; make it longer"
    );
    let a = a.wait_with_output().unwrap();
    assert!(a.status.success(), "{}", text(&a.stderr));
    assert_eq!(
        assert_nothing_wrong(&root),
        ["ns/long-v0", "ns/short-v0"],
        "{}",
        text(&a.stdout)
    );
    let long = envc(&["dataset", "show", &format!("{r}/ns/long-v0")]);
    assert!(
        text(&long.stdout).contains("episodes          400"),
        "{}",
        text(&long.stdout)
    );
    // The real Minari iterates every episode too, when the venv is there.
    let py = concat!(env!("CARGO_MANIFEST_DIR"), "/../.venv/bin/python");
    if Path::new(py).exists() {
        let o = Command::new(py)
            .args([
                "-c",
                "import minari; ds = minari.load_dataset('ns/long-v0'); \
                 print(sum(len(e) for e in ds.iterate_episodes()), ds.total_steps)",
            ])
            .env("MINARI_DATASETS_PATH", r)
            .output()
            .unwrap();
        let out = text(&o.stdout);
        let v: Vec<&str> = out.split_whitespace().collect();
        assert!(
            o.status.success() && v.len() == 2 && v[0] == v[1],
            "{out}{}",
            text(&o.stderr)
        );
    }
    assert!(locks(&root).is_empty());
    let _ = std::fs::remove_dir_all(&root);
}

/// A tiny seeded generator (splitmix64) for the kill points.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[test]
fn kill_9_at_random_points_leaves_nothing_wrong_and_the_next_collect_cleans_up() {
    let root = tmp("kill");
    let r = root.to_str().unwrap();
    let mut seed = 16u64;
    // Collect serves tasks and mazes; multi-agent specs answer E0602 (README's command matrix).
    for (spec, episodes) in [("Hopper-v5", "2000"), ("PointMaze_UMaze-v3", "500")] {
        for format in ["arrow", "hdf5"] {
            let id = format!("kk/{}-{format}-v0", spec.to_lowercase().replace('_', "-"));
            let mut child = spawn(&collect_args(spec, r, &id, episodes, format));
            wait_for_staging(&root, &mut child);
            let delay = 20 + splitmix(&mut seed) % 400;
            std::thread::sleep(Duration::from_millis(delay));
            assert!(
                child.try_wait().unwrap().is_none(),
                "{spec} {format} finished within {delay} ms; collect more episodes"
            );
            child.kill().unwrap(); // SIGKILL
            child.wait().unwrap();
            assert!(
                !root.join(&id).exists(),
                "{id} published after a kill at {delay} ms"
            );
            assert_nothing_wrong(&root);
            let left = staging_dirs(&root);
            assert_eq!(left.len(), 1, "{left:?}");
            let staged = left[0].clone();
            // The next collection of the same id works and names what it removed.
            let o = envc(&collect_args(spec, r, &id, "2", format));
            assert!(o.status.success(), "{}", text(&o.stderr));
            let out = text(&o.stdout);
            assert!(
                out.contains("removed the staging directory of an interrupted collection")
                    && out.contains(&staged.display().to_string()),
                "{out}"
            );
            assert!(!staged.exists() && locks(&root).is_empty());
        }
    }
    assert_eq!(
        assert_nothing_wrong(&root),
        [
            "kk/hopper-v5-arrow-v0",
            "kk/hopper-v5-hdf5-v0",
            "kk/pointmaze-umaze-v3-arrow-v0",
            "kk/pointmaze-umaze-v3-hdf5-v0"
        ]
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn a_staging_directory_removed_under_a_running_collection_is_an_error() {
    let root = tmp("removed");
    let r = root.to_str().unwrap();
    for format in ["arrow", "hdf5"] {
        let id = format!("gone/{format}-v0");
        let mut child = spawn(&collect_args("Hopper-v5", r, &id, "600", format));
        wait_for_staging(&root, &mut child);
        std::thread::sleep(Duration::from_millis(150));
        let staged = staging_dirs(&root)[0].clone();
        // `rm -rf` races the writer adding files (ENOTEMPTY): repeat until it is gone.
        let t0 = Instant::now();
        while std::fs::remove_dir_all(&staged).is_err() && staged.exists() {
            assert!(t0.elapsed() < Duration::from_secs(10));
        }
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{format}: {}", text(&o.stdout));
        assert_one_clean_line(&text(&o.stderr), "E1209");
        assert!(!root.join(&id).exists());
        assert!(locks(&root).is_empty(), "{format}: its lock file stays");
        assert!(assert_nothing_wrong(&root).is_empty());
    }
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn nested_and_escaping_dataset_ids_are_refused() {
    let root = tmp("nested");
    let r = root.to_str().unwrap();
    let base = envc(&collect_args(
        "InvertedPendulum-v5",
        r,
        "tt/base-v0",
        "2",
        "arrow",
    ));
    assert!(base.status.success(), "{}", text(&base.stderr));
    let inner = envc(&collect_args(
        "InvertedPendulum-v5",
        r,
        "ns/sub-v0/a-v0",
        "1",
        "arrow",
    ));
    assert!(inner.status.success(), "{}", text(&inner.stderr));
    for (id, code) in [
        // Into episode 0 of tt/base-v0, and into its data directory.
        ("tt/base-v0/data/0/x-v0", "E1208"),
        ("tt/base-v0/data/x-v0", "E1208"),
        ("tt/base-v0/x-v0", "E1208"),
        // A namespace that holds a dataset is not a dataset.
        ("ns/sub-v0", "E1208"),
        ("tt/base-v0", "E1202"),
        ("../x-v0", "E1201"),
        ("/tmp/x-v0", "E1201"),
        ("ns//x-v0", "E1201"),
        (".envc-staging/x-v0", "E1201"),
        ("ns/./x-v0", "E1201"),
    ] {
        let o = envc(&collect_args("InvertedPendulum-v5", r, id, "1", "arrow"));
        assert_eq!(o.status.code(), Some(2), "{id} accepted");
        assert_one_clean_line(&text(&o.stderr), code);
    }
    assert_eq!(
        assert_nothing_wrong(&root),
        ["ns/sub-v0/a-v0", "tt/base-v0"]
    );
    let show = envc(&["dataset", "show", &format!("{r}/tt/base-v0")]);
    assert!(text(&show.stdout).contains("episodes          2"));
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn collect_into_an_unwritable_root_or_a_full_disk_fails_cleanly() {
    // A root under a regular file fails even for root.
    let base = tmp("unwritable");
    std::fs::write(base.join("file"), b"x").unwrap();
    let under_file = base.join("file").join("root");
    let o = envc(&collect_args(
        "InvertedPendulum-v5",
        under_file.to_str().unwrap(),
        "xx/y-v0",
        "1",
        "arrow",
    ));
    assert_eq!(o.status.code(), Some(2));
    assert_one_clean_line(&text(&o.stderr), "E1203");
    assert!(
        text(&o.stderr).contains("Not a directory"),
        "{}",
        text(&o.stderr)
    );
    if !unshare_works() {
        return;
    }
    let d = base.join("mnt");
    std::fs::create_dir_all(&d).unwrap();
    let m = d.to_str().unwrap();
    for format in ["arrow", "hdf5"] {
        // Read-only: a read-only bind mount (chmod means nothing to root).
        let args = collect_args("InvertedPendulum-v5", m, "xx/y-v0", "1", format).join(" ");
        let o = in_mount_ns(&format!(
            "mount --bind {m} {m} && mount -o remount,bind,ro {m} && \"$ENVC\" {args}"
        ));
        assert_eq!(o.status.code(), Some(2), "{format}: {}", text(&o.stdout));
        assert_one_clean_line(&text(&o.stderr), "E1203");
        assert!(text(&o.stderr).contains("Read-only file system"));
        // Too small: a 1 MiB tmpfs; 400 Hopper episodes (~9000 steps) take a few. Refused from
        // the first 8 episodes' size (E1211), before the disk is full.
        let args = collect_args("Hopper-v5", m, "xx/y-v0", "400", format).join(" ");
        let o = in_mount_ns(&format!(
            "mount -t tmpfs -o size=1m tmpfs {m} && \"$ENVC\" {args}; rc=$?; \
             find {m} -name '*.arrow' -o -name '*.hdf5' -o -name '*.lock' | wc -l; exit $rc"
        ));
        assert_eq!(o.status.code(), Some(2), "{format}: {}", text(&o.stdout));
        let err = text(&o.stderr);
        assert_one_clean_line(&err, "E1211");
        assert!(err.contains("are free"), "{err}");
        assert_eq!(text(&o.stdout).trim(), "0", "{format}");
        // Full within the first episodes (before any estimate): the disk's own error (E1203).
        let args = collect_args("Hopper-v5", m, "xx/y-v0", "8", format).join(" ");
        let o = in_mount_ns(&format!(
            "mount -t tmpfs -o size=32k tmpfs {m} && \"$ENVC\" {args}; rc=$?; \
             find {m} -name '*.arrow' -o -name '*.hdf5' -o -name '*.lock' | wc -l; exit $rc"
        ));
        assert_eq!(o.status.code(), Some(2), "{format}: {}", text(&o.stdout));
        let err = text(&o.stderr);
        assert_one_clean_line(&err, "E1203");
        assert!(err.contains("No space left on device"), "{err}");
        // Nothing is left on the full disk: no episodes, no lock.
        assert_eq!(text(&o.stdout).trim(), "0", "{format}");
    }
    let _ = std::fs::remove_dir_all(&base);
}

fn write_actions(path: &Path, steps: usize, width: usize) {
    let a = ndarray::Array2::<f64>::zeros((steps, width));
    ndarray_npy::write_npy(path, &a).unwrap();
}

#[test]
fn rollout_never_overwrites_its_input_and_replaces_out_whole() {
    let d = tmp("rollout");
    let a = d.join("A.npy");
    write_actions(&a, 5, 3);
    let before = std::fs::read(&a).unwrap();
    std::fs::hard_link(&a, d.join("hard.npz")).unwrap();
    std::os::unix::fs::symlink(&a, d.join("soft.npz")).unwrap();
    for out in ["A.npy", "hard.npz", "soft.npz"] {
        let out = d.join(out);
        let o = envc(&[
            "rollout",
            "Hopper-v5",
            "--seed",
            "0",
            "--actions",
            a.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert_one_clean_line(&text(&o.stderr), "E1411");
        assert_eq!(std::fs::read(&a).unwrap(), before);
    }
    // An existing --out is replaced whole; no temporary file stays.
    let t = d.join("T.npz");
    std::fs::write(&t, b"old").unwrap();
    let o = envc(&[
        "rollout",
        "Hopper-v5",
        "--seed",
        "0",
        "--actions",
        a.to_str().unwrap(),
        "--out",
        t.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(&std::fs::read(&t).unwrap()[..2], b"PK");
    let mut names: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["A.npy", "T.npz", "hard.npz", "soft.npz"]);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn rollout_onto_a_full_disk_keeps_the_old_file_and_says_so_once() {
    if !unshare_works() {
        return;
    }
    let d = tmp("rollout-full");
    let a = d.join("A.npy");
    write_actions(&a, 2000, 17); // Humanoid: 2000 × 348 observations, ~5.6 MB
    let m = d.join("mnt");
    std::fs::create_dir_all(&m).unwrap();
    let (m, a) = (m.to_str().unwrap(), a.to_str().unwrap());
    for (spec, policy) in [
        ("Humanoid-v5", format!("--actions {a}")),
        ("PointMaze_UMaze-v3", "--policy random --steps 20000".into()),
        ("MaMuJoCo-Ant-v1", "--policy random --steps 3000".into()),
    ] {
        let o = in_mount_ns(&format!(
            "mount -t tmpfs -o size=256k tmpfs {m} && printf old > {m}/T.npz && \
             \"$ENVC\" rollout {spec} --seed 0 {policy} --auto-reset --out {m}/T.npz; rc=$?; \
             cat {m}/T.npz; echo; ls -A {m}; exit $rc"
        ));
        assert_eq!(o.status.code(), Some(2), "{spec}: {}", text(&o.stderr));
        let err = text(&o.stderr);
        assert_one_clean_line(&err, "E1410");
        assert!(
            err.contains("No space left on device") && err.contains("existing file is unchanged"),
            "{err}"
        );
        // The old file, and nothing else.
        assert_eq!(text(&o.stdout), "old\nT.npz\n", "{spec}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn envc_new_onto_a_full_disk_leaves_no_half_made_crate() {
    if !unshare_works() {
        return;
    }
    let d = tmp("new-full");
    let m = d.join("mnt");
    std::fs::create_dir_all(&m).unwrap();
    let m = m.to_str().unwrap();
    // 32 KiB: the spec and the small files fit, the lock file (~46 KB) does not.
    let o = in_mount_ns(&format!(
        "mount -t tmpfs -o size=32k tmpfs {m} && \"$ENVC\" new {m}/mine; rc=$?; ls -A {m}; exit $rc"
    ));
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert_one_clean_line(&err, "E1410");
    assert!(err.contains("No space left on device"), "{err}");
    assert_eq!(text(&o.stdout), "", "nothing is left on the disk");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_output_never_replaces_a_device_or_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let d = tmp("out-fifo");
    std::fs::create_dir_all(&d).unwrap();
    // A FIFO stands in for /dev/null: renaming the finished file over either would replace the
    // node itself (a fuzzing run once turned /dev/urandom into a zip file this way).
    for name in ["t.npz", "v.mp4"] {
        let fifo = d.join(name);
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        let args: Vec<&str> = if name.ends_with(".npz") {
            vec![
                "rollout",
                "Hopper-v5",
                "--policy",
                "zero",
                "--steps",
                "3",
                "--out",
            ]
        } else {
            vec!["render", "Hopper-v5", "--max-steps", "2", "--out"]
        };
        let o = Command::new(ENVC)
            .args(&args)
            .arg(&fifo)
            .output()
            .expect("run envc");
        assert_eq!(o.status.code(), Some(2), "{name}: {}", text(&o.stderr));
        assert_one_clean_line(&text(&o.stderr), "E1410");
        let m = std::fs::symlink_metadata(&fifo).unwrap();
        assert!(m.file_type().is_fifo(), "{name} is still the FIFO");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// `envc dataset show` under a 20 s wall clock (a FIFO episode used to block it for ever).
fn envc_timed(args: &[&str]) -> Output {
    Command::new("timeout")
        .args(["-s", "KILL", "20", ENVC])
        .args(args)
        .output()
        .expect("run envc")
}

#[test]
fn dataset_show_verifies_before_printing_and_never_opens_a_fifo() {
    let root = tmp("show-verify");
    let r = root.to_str().unwrap();
    let o = envc(&collect_args("Hopper-v5", r, "show/fifo-v0", "2", "arrow"));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = envc(&collect_args("Hopper-v5", r, "show/cut-v0", "2", "arrow"));
    assert!(o.status.success(), "{}", text(&o.stderr));
    let episode_file = |id: &str| {
        let dir = root.join(id).join("data/1");
        std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|x| x == "arrow"))
            .unwrap()
    };
    // A FIFO in place of an episode: an error at once, not a process blocked in open().
    let fifo = episode_file("show/fifo-v0");
    std::fs::remove_file(&fifo).unwrap();
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let started = Instant::now();
    let o = envc_timed(&[
        "dataset",
        "show",
        root.join("show/fifo-v0").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(started.elapsed() < Duration::from_secs(15));
    assert!(text(&o.stderr).contains("E1203"), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("FIFO"), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout), "", "nothing printed before the error");
    // A truncated episode: E1204, and no summary printed before it.
    let cut = episode_file("show/cut-v0");
    let bytes = std::fs::read(&cut).unwrap();
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = envc_timed(&[
        "dataset",
        "show",
        root.join("show/cut-v0").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("E1204"), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout), "", "nothing printed before the error");
    // --no-episodes still shows the metadata alone.
    let o = envc_timed(&[
        "dataset",
        "show",
        root.join("show/cut-v0").to_str().unwrap(),
        "--no-episodes",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("show/cut-v0"));
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn sigint_sigterm_and_sighup_stop_a_collection_and_remove_its_staging() {
    for (sig, name) in [
        (libc::SIGINT, "int"),
        (libc::SIGTERM, "term"),
        (libc::SIGHUP, "hup"),
    ] {
        let root = tmp(&format!("signal-{name}"));
        let id = format!("sig/{name}-v0");
        let mut child = spawn(&collect_args(
            "Hopper-v5",
            root.to_str().unwrap(),
            &id,
            "5000",
            "arrow",
        ));
        wait_for_staging(&root, &mut child);
        std::thread::sleep(Duration::from_millis(100));
        // SAFETY: a signal to the child this test spawned.
        unsafe {
            libc::kill(child.id() as libc::pid_t, sig);
        }
        let t0 = Instant::now();
        let out = child.wait_with_output().unwrap();
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "{name}: slow to stop"
        );
        assert!(!out.status.success(), "{name}");
        assert!(
            text(&out.stderr).contains("interrupted"),
            "{name}: {}",
            text(&out.stderr)
        );
        assert!(staging_dirs(&root).is_empty(), "{name}: staging left");
        assert!(locks(&root).is_empty(), "{name}: lock left");
        assert!(!root.join(&id).exists());
        let _ = std::fs::remove_dir_all(&root);
    }
}
