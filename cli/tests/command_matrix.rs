//! Every command on every kind of spec, as the README's command matrix promises: the test reads
//! the table between the `command-matrix` markers and runs each cell on a bundled id and on a spec
//! file of the user's own (outside `specs/`). `yes` must succeed; `E0602` must fail with status 2
//! and that code.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

fn envc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_envc"))
        .args(args)
        .output()
        .expect("run envc")
}

/// The README table: (command, [task, maze, multi-agent] cells).
fn matrix() -> Vec<(String, [String; 3])> {
    let readme = std::fs::read_to_string(format!("{ROOT}/README.md")).unwrap();
    let start = readme
        .find("<!-- command-matrix")
        .expect("matrix start marker");
    let end = readme
        .find("<!-- end command-matrix -->")
        .expect("matrix end marker");
    readme[start..end]
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<String> = l
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect();
            assert_eq!(cells.len(), 4, "{l}");
            let cmd = cells[0].trim_matches('`').to_string();
            (cmd, [cells[1].clone(), cells[2].clone(), cells[3].clone()])
        })
        .collect()
}

/// A float64 `.npy` of zeros [rows, cols].
fn write_npy(path: &Path, rows: usize, cols: usize) {
    ndarray_npy::write_npy(path, &ndarray::Array2::<f64>::zeros((rows, cols))).unwrap();
}

struct Case {
    kind: usize,
    /// The bundled id, then the user's own spec file.
    args: [String; 2],
    act_dim: usize,
}

/// The user's own specs: a task, a maze and a factorization written outside `specs/`, pointing at
/// envc's models and robots by absolute path.
fn own_specs(dir: &Path) -> [PathBuf; 3] {
    let root = Path::new(ROOT).canonicalize().unwrap();
    let r = root.display();
    let task = dir.join("my_hopper.toml");
    let hopper = std::fs::read_to_string(root.join("specs/gymnasium/hopper.toml")).unwrap();
    let hopper = hopper
        .replace("../../assets/", &format!("{r}/assets/"))
        .replace("\"Hopper-v5\"", "\"MyHopper-v0\"");
    std::fs::write(&task, hopper).unwrap();
    let maze = dir.join("my_maze.toml");
    std::fs::write(
        &maze,
        format!(
            "[maze]\nid = \"MyMaze-v0\"\nrobot = \"{r}/specs/robotics/maze/point.toml\"\n\
             map = \"\"\"\n1 1 1 1 1\n1 r 0 g 1\n1 1 1 1 1\n\"\"\"\nmaze_size_scaling = 1.0\n\
             maze_height = 0.4\nmax_episode_steps = 50\nvelocity_clip = 5.0\n"
        ),
    )
    .unwrap();
    let agents = dir.join("my_agents.toml");
    let cheetah = std::fs::read_to_string(root.join("specs/mamujoco/half_cheetah.toml")).unwrap();
    let cheetah = cheetah
        .replace(
            "\"../gymnasium/half_cheetah.toml\"",
            &format!("\"{r}/specs/gymnasium/half_cheetah.toml\""),
        )
        .replace("\"MaMuJoCo-HalfCheetah-v1\"", "\"MyCheetahAgents-v0\"");
    std::fs::write(&agents, cheetah).unwrap();
    [task, maze, agents]
}

/// The files a cell's command reads or writes, named after its case (`tag`).
struct CellFiles {
    tag: String,
    /// Zero actions for `rollout`.
    actions: PathBuf,
    /// `rollout`'s output.
    out: PathBuf,
    /// `collect`'s root and dataset id.
    ds_root: PathBuf,
    ds_id: String,
}

/// Run one cell; returns the failure text, if any.
fn cell(cmd: &str, expect: &str, case: &Case, own: bool, dir: &Path) -> Option<String> {
    let spec = case.args[usize::from(own)].as_str();
    let tag = format!("{}-{}", case.kind, u8::from(own));
    let actions = dir.join(format!("a{}.npy", case.act_dim));
    write_npy(&actions, 5, case.act_dim);
    let files = CellFiles {
        actions,
        out: dir.join(format!("{tag}.npz")),
        ds_root: dir.join("datasets"),
        ds_id: format!("matrix/k{tag}-v0"),
        tag,
    };
    let args = match cell_args(cmd, expect, spec, own, dir, &files) {
        Ok(Some(args)) => args,
        Ok(None) => return None,
        Err(e) => return Some(e),
    };
    let o = envc(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    let what = format!("`envc {}` ({expect})", args.join(" "));
    if expect.starts_with("yes") {
        if o.status.code() != Some(0) {
            return Some(format!("{what}: status {:?}\n{stderr}", o.status.code()));
        }
        succeeded(cmd, case, &what, &stdout, dir, &files)
    } else if expect.starts_with("E0602") {
        (o.status.code() != Some(2) || !stderr.contains("E0602")).then(|| {
            format!(
                "{what}: expected status 2 with E0602, got {:?}\n{stderr}",
                o.status.code()
            )
        })
    } else {
        Some(format!("unknown matrix cell `{expect}` for `{cmd}`"))
    }
}

/// The command line of a cell: `None` for a cell that is not run, an error for an unknown
/// command.
fn cell_args(
    cmd: &str,
    expect: &str,
    spec: &str,
    own: bool,
    dir: &Path,
    files: &CellFiles,
) -> Result<Option<Vec<String>>, String> {
    let CellFiles {
        tag,
        actions,
        out,
        ds_root,
        ds_id,
    } = files;
    let root_s = ds_root.display().to_string();
    Ok(Some(match cmd {
        "list" if own => return Ok(None), // `list` shows the bundled ids only
        "list" => vec!["list".into(), "--format".into(), "json".into()],
        "check" | "show" => vec![cmd.into(), spec.into()],
        "run" => ["run", spec, "--episodes", "1", "--max-steps", "30"]
            .map(String::from)
            .to_vec(),
        "rollout" => vec![
            "rollout".into(),
            spec.into(),
            "--seed".into(),
            "0".into(),
            "--actions".into(),
            actions.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ],
        "collect" => [
            "collect",
            spec,
            "--dataset-id",
            ds_id,
            "--episodes",
            "1",
            "--policy",
            "random",
            "--seed",
            "0",
            "--root",
            &root_s,
        ]
        .map(String::from)
        .to_vec(),
        "dataset show" if expect.starts_with("yes") => {
            // The dataset this kind's `collect` cell wrote.
            let p = ds_root.join(ds_id);
            vec!["dataset".into(), "show".into(), p.display().to_string()]
        }
        "dataset show" => vec!["dataset".into(), "show".into(), spec.into()],
        "diff" => vec!["diff".into(), spec.into(), spec.into()],
        "bench" => [
            "bench",
            spec,
            "--seconds",
            "0.2",
            "--rounds",
            "1",
            "--envs",
            "2",
        ]
        .map(String::from)
        .to_vec(),
        "new" => vec![
            "new".into(),
            dir.join(format!("crate-{tag}")).display().to_string(),
            "--spec".into(),
            spec.into(),
        ],
        "render" => vec![
            "render".into(),
            spec.into(),
            "--max-steps".into(),
            "3".into(),
            "--size".into(),
            "64x48".into(),
            "--out".into(),
            dir.join(format!("{tag}.mp4")).display().to_string(),
        ],
        other => return Err(format!("the matrix names an unknown command `{other}`")),
    }))
}

/// What a `yes` cell that exited 0 must also have done; the failure text, if any.
fn succeeded(
    cmd: &str,
    case: &Case,
    what: &str,
    stdout: &str,
    dir: &Path,
    files: &CellFiles,
) -> Option<String> {
    if cmd == "list" {
        let v: serde_json::Value = serde_json::from_str(stdout).unwrap();
        let kind = ["task", "maze", "agents"][case.kind];
        let found = v.as_array().unwrap().iter().any(|r| {
            r["id"].as_str() == Some(case.args[0].as_str()) && r["kind"].as_str() == Some(kind)
        });
        if !found {
            return Some(format!("{what}: no {kind} row for {}", case.args[0]));
        }
    }
    if cmd == "render" {
        // The video plays: ffprobe decodes it back (frame count and size; a reset frame and
        // one per step, three steps unless the episode ended first).
        let video = dir.join(format!("{}.mp4", files.tag));
        let probe = Command::new("ffprobe")
            .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
            .args([
                "-show_entries",
                "stream=nb_read_frames,width,height",
                "-of",
                "csv=p=0",
            ])
            .arg(&video)
            .output();
        let got = probe.map(|p| String::from_utf8_lossy(&p.stdout).trim().to_string());
        if !matches!(got.as_deref(), Ok("64,48,4")) {
            return Some(format!("{what}: ffprobe says {got:?}, expected 64,48,4"));
        }
    }
    // A dataset says what made it: the MuJoCo and envc versions and the spec it recorded.
    if cmd == "dataset show"
        && !(stdout.contains("made with         MuJoCo 3.17.0, envc ")
            && stdout.contains("files recorded)"))
    {
        return Some(format!("{what}: no versions or spec record in\n{stdout}"));
    }
    if cmd == "rollout" && !files.out.is_file() {
        return Some(format!("{what}: no {}", files.out.display()));
    }
    None
}

#[test]
fn every_command_on_every_kind() {
    let dir = std::env::temp_dir().join(format!("envc-matrix-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let own = own_specs(&dir);
    let cases = [
        ("Hopper-v5", 3),
        ("PointMaze_UMaze-v3", 2),
        ("MaMuJoCo-HalfCheetah-v1", 6),
    ]
    .into_iter()
    .enumerate()
    .map(|(kind, (id, act_dim))| Case {
        kind,
        args: [id.to_string(), own[kind].display().to_string()],
        act_dim,
    })
    .collect::<Vec<_>>();
    let rows = matrix();
    let commands: Vec<&str> = rows.iter().map(|(c, _)| c.as_str()).collect();
    assert_eq!(
        commands,
        [
            "list",
            "check",
            "show",
            "run",
            "rollout",
            "collect",
            "dataset show",
            "diff",
            "bench",
            "new",
            "render"
        ],
        "the README matrix lists every command that takes a spec, in this order"
    );
    let mut failures = vec![];
    for (cmd, cells) in &rows {
        for case in &cases {
            for own in [false, true] {
                failures.extend(cell(cmd, &cells[case.kind], case, own, &dir));
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
