//! docs/tutorial.md and docs/pick-and-place.md run as written: their `LANG file=NAME` blocks
//! (TOML, MJCF, URDF) are written (or, with `append`, appended) into a fresh directory and their
//! `sh` blocks run there, in page order, with `envc` on the PATH and `ENVC_REPO` set (no block
//! needs it: a wheel user follows the page as is). Blocks marked `no-test` (a cargo build, Python)
//! and `python` blocks are checked elsewhere (scripts/test.sh, tests/python).

use std::path::Path;
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

enum Block {
    File {
        name: String,
        append: bool,
        text: String,
    },
    Sh(String),
}

fn blocks(md: &str) -> Vec<Block> {
    let mut out = vec![];
    let mut lines = md.lines();
    while let Some(l) = lines.next() {
        let Some(info) = l.strip_prefix("```") else {
            continue;
        };
        let body: Vec<&str> = lines
            .by_ref()
            .take_while(|l| !l.starts_with("```"))
            .collect();
        let text = body.join("\n") + "\n";
        let words: Vec<&str> = info.split_whitespace().collect();
        match words.as_slice() {
            [_lang, file, rest @ ..] if file.starts_with("file=") => out.push(Block::File {
                name: file["file=".len()..].to_string(),
                append: rest.contains(&"append"),
                text,
            }),
            ["sh"] => out.push(Block::Sh(text)),
            _ => {}
        }
    }
    out
}

/// Writes the page's files and runs its `sh` blocks in a fresh directory, which it returns;
/// `(files, sh blocks)` counted.
fn run_page(page: &str, tag: &str) -> (std::path::PathBuf, usize, usize) {
    let md = std::fs::read_to_string(format!("{ROOT}/docs/{page}")).unwrap();
    let dir = std::env::temp_dir().join(format!("envc-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bin = Path::new(env!("CARGO_BIN_EXE_envc")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let root = Path::new(ROOT).canonicalize().unwrap();
    let (mut files, mut commands) = (0, 0);
    for b in blocks(&md) {
        match b {
            Block::File { name, append, text } => {
                let p = dir.join(name);
                let mut all = if append {
                    std::fs::read_to_string(&p).unwrap()
                } else {
                    String::new()
                };
                all.push_str(&text);
                std::fs::write(&p, all).unwrap();
                files += 1;
            }
            Block::Sh(script) => {
                let o = Command::new("sh")
                    .args(["-euc", &script])
                    .current_dir(&dir)
                    .env("PATH", &path)
                    .env("ENVC_REPO", &root)
                    .output()
                    .unwrap();
                assert!(
                    o.status.success(),
                    "{page} block failed:\n{script}\nstdout:\n{}\nstderr:\n{}",
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr)
                );
                commands += 1;
            }
        }
    }
    (dir, files, commands)
}

#[test]
fn the_tutorial_runs_as_written() {
    let (dir, files, commands) = run_page("tutorial.md", "tutorial");
    assert!(
        files >= 2 && commands >= 6,
        "{files} files, {commands} blocks"
    );
    // What the page promises: a trajectory, a dataset, a crate.
    assert!(dir.join("arm.npz").is_file());
    assert!(
        dir.join("datasets/me/my-arm-random-v0/data/metadata.json")
            .is_file()
    );
    assert!(dir.join("my-arm-crate/src/main.rs").is_file());
    std::fs::remove_dir_all(&dir).ok();
}

/// docs/pick-and-place.md runs as written, and its two files are the bundled example's.
#[test]
fn the_pick_and_place_guide_runs_as_written() {
    let (dir, files, commands) = run_page("pick-and-place.md", "pick-and-place");
    assert!(
        files >= 6 && commands >= 2,
        "{files} files, {commands} blocks"
    );
    let read = |p: std::path::PathBuf| std::fs::read_to_string(p).unwrap();
    assert_eq!(
        read(dir.join("arm.xml")),
        read(Path::new(ROOT).join("assets/examples/arm/arm.xml"))
    );
    // The same lines (the bundled file has blank lines between the page's blocks).
    let lines = |t: String| -> Vec<String> {
        t.lines()
            .filter(|l| !l.is_empty())
            .map(str::to_string)
            .collect()
    };
    assert_eq!(
        lines(read(dir.join("pick.toml")).replace(
            "default = \"arm.xml\"",
            "default = \"../../assets/examples/arm/arm.xml\""
        )),
        lines(read(
            Path::new(ROOT).join("specs/examples/arm_pick_and_place.toml")
        ))
    );
    std::fs::remove_dir_all(&dir).ok();
}
