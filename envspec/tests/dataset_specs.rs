//! Dataset specs (`envspec::dataset_spec`): the bundled suite reads as published, mistakes are
//! E1801 at their line and column, the read is recorded, and the reference-score rewrite changes
//! that table only.

use envspec::Code;
use envspec::dataset_spec::{self, Budget, DatasetSpec, RefScores, StorageFormat};
use envspec::source::Reader;

/// The published suite: 28 ids, with the generation scripts' budgets and algorithms.
const PUBLISHED: &[(&str, u64, &str)] = &[
    ("mujoco/ant/expert-v0", 2_000_000, "SB3/SAC"),
    ("mujoco/ant/medium-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/ant/simple-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/halfcheetah/expert-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/halfcheetah/medium-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/halfcheetah/simple-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/hopper/expert-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/hopper/medium-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/hopper/simple-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/humanoid/expert-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/humanoid/medium-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/humanoid/simple-v0", 1_000_000, "SB3/TQC"),
    ("mujoco/humanoidstandup/expert-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/humanoidstandup/medium-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/humanoidstandup/simple-v0", 1_000_000, "SB3/SAC"),
    (
        "mujoco/inverteddoublependulum/expert-v0",
        100_000,
        "SB3/SAC",
    ),
    (
        "mujoco/inverteddoublependulum/medium-v0",
        100_000,
        "SB3/SAC",
    ),
    ("mujoco/invertedpendulum/expert-v0", 100_000, "SB3/SAC"),
    ("mujoco/invertedpendulum/medium-v0", 100_000, "SB3/SAC"),
    ("mujoco/pusher/expert-v0", 500_000, "SB3/SAC"),
    ("mujoco/pusher/medium-v0", 500_000, "SB3/SAC"),
    ("mujoco/reacher/expert-v0", 500_000, "SB3/SAC"),
    ("mujoco/reacher/medium-v0", 500_000, "SB3/SAC"),
    ("mujoco/swimmer/expert-v0", 1_000_000, "SB3/PPO"),
    ("mujoco/swimmer/medium-v0", 1_000_000, "SB3/PPO"),
    ("mujoco/walker2d/expert-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/walker2d/medium-v0", 1_000_000, "SB3/SAC"),
    ("mujoco/walker2d/simple-v0", 1_000_000, "SB3/SAC"),
];

const SPEC: &str = "[dataset]\nid = \"t/x-v0\"\ntier = \"x\"\nenv = \"Hopper-v5\"\nsteps = 10\nseed = 1\n[policy]\nfile = \"p.npz\"\nmode = \"deterministic\"\n[metadata]\nalgorithm_name = \"a\"\nauthor = []\ndescription = \"d\"\n";

/// A scratch directory of this test process, removed when dropped.
fn scratch(name: &str) -> crate::scratch::ScratchDir {
    crate::scratch::ScratchDir::new(name)
}

fn parse(text: &str) -> Result<DatasetSpec, envspec::Diagnostic> {
    dataset_spec::parse(&envspec::SourceFile::new("d.toml", text.to_string()))
}

fn position(d: &envspec::Diagnostic) -> String {
    d.position().unwrap_or_default()
}

#[test]
fn the_bundled_suite_is_the_published_one() {
    let specs: Vec<DatasetSpec> = dataset_spec::bundled()
        .iter()
        .map(|p| dataset_spec::read(p).unwrap())
        .collect();
    let got: Vec<(&str, u64, &str)> = specs
        .iter()
        .map(|s| {
            let Budget::Steps(n) = s.budget else {
                panic!("{}: a step budget", s.dataset_id)
            };
            (s.dataset_id.as_str(), n, s.algorithm_name.as_str())
        })
        .collect();
    assert_eq!(got, PUBLISHED);
    for s in &specs {
        // The file sits at its id; the tier is the id's name; episode k is reset with 123 + k
        // (ant/expert's own script: 12345); every one is stored as Arrow and says how to train.
        assert!(s.path.ends_with(format!("{}.toml", s.dataset_id)));
        assert!(s.dataset_id.ends_with(&format!("/{}-v0", s.tier)));
        let seed = if s.dataset_id == "mujoco/ant/expert-v0" {
            12345
        } else {
            123
        };
        assert_eq!(s.seed, seed, "{}", s.dataset_id);
        assert_eq!(s.format, StorageFormat::Arrow);
        assert!(!s.description.is_empty());
        assert!(s.document.contains_key("train"), "{}", s.dataset_id);
    }
    // An id opens the bundled file.
    let hopper = dataset_spec::open("mujoco/hopper/simple-v0").unwrap();
    assert_eq!(hopper.env, "Hopper-v5");
    assert!(hopper.policy_file.ends_with("hopper-v5-sac-simple.npz"));
}

#[test]
fn mistakes_are_e1801_at_their_line_and_column() {
    let both = SPEC.replace("seed = 1\n", "episodes = 2\nseed = 1\n");
    let e = parse(&both).unwrap_err();
    assert_eq!(e.code, Code::E1801);
    assert_eq!(position(&e), "d.toml:6:1");
    assert_eq!(e.message, "give `steps` or `episodes`, not both");
    // An unknown key is refused where it is written, with the keys the table has.
    let e = parse(&SPEC.replace("mode = ", "mood = ")).unwrap_err();
    assert_eq!(e.code, Code::E1801);
    assert_eq!(position(&e), "d.toml:9:1");
    assert!(
        e.message.starts_with("unknown field `mood`, expected"),
        "{e}"
    );
    // Not TOML: the unclosed string, at its line.
    let e = parse(&SPEC.replace("tier = \"x\"", "tier = \"x")).unwrap_err();
    assert_eq!(e.code, Code::E1801);
    assert!(position(&e).starts_with("d.toml:3:"), "{e}");
    // A wrong type, at its value.
    let e = parse(&SPEC.replace("seed = 1", "seed = \"one\"")).unwrap_err();
    assert_eq!(position(&e), "d.toml:6:8");
    // Checks made after parsing point at their key.
    let e = parse(&SPEC.replace("steps = 10", "steps = 100000000000")).unwrap_err();
    assert_eq!(position(&e), "d.toml:5:1");
    assert!(e.message.contains("beyond envc's limit"), "{e}");
    let e = parse(&SPEC.replace("seed = 1", "seed = 1\nformat = \"csv\"")).unwrap_err();
    assert_eq!(position(&e), "d.toml:7:1");
    let scores = format!(
        "{SPEC}[reference_scores]\nref_min_score = 1.0\nref_max_score = 1.0\nnum_episodes_average_score = 3\n"
    );
    let e = parse(&scores).unwrap_err();
    assert_eq!(position(&e), "d.toml:16:1");
}

#[test]
fn the_read_is_recorded_and_a_fifo_is_refused() {
    let dir = scratch("dataset-read");
    let path = dir.join("d.toml");
    std::fs::write(&path, SPEC).unwrap();
    let mut reader = Reader::disk();
    let spec = reader.run(|| dataset_spec::read(&path)).unwrap();
    assert_eq!(spec.budget, Budget::Steps(10));
    assert_eq!(spec.policy_file, dir.join("p.npz"));
    assert_eq!(reader.files().len(), 1);
    assert_eq!(reader.files()[0].path, path);
    assert_eq!(
        reader.files()[0].hash,
        Some(envspec::source::fnv1a(SPEC.as_bytes()))
    );
    // A FIFO is refused before it is opened (opening it would block).
    let fifo = dir.join("fifo.toml");
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let e = dataset_spec::open(fifo.to_str().unwrap()).unwrap_err();
        assert_eq!(e.code, Code::E1801);
        assert!(e.message.contains("not a regular file"), "{e}");
    }
    // Neither a file nor a bundled id.
    let e = dataset_spec::open("mujoco/hopper/none-v0").unwrap_err();
    assert_eq!(e.code, Code::E1801);
    assert!(
        e.message
            .contains("neither a dataset spec file nor a bundled dataset id")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_reference_score_rewrite_changes_that_table_only() {
    let dir = scratch("dataset-edit");
    let path = dir.join("d.toml");
    let scores = RefScores {
        ref_min_score: -12.5,
        ref_max_score: 3000.25,
        num_episodes_average_score: 100,
    };
    // No table yet: a new one before [train], the rest as written, comments included.
    let spec = SPEC.replace("seed = 1\n", "# why this seed\nseed = 1 # inline\n")
        + "\n[train]\nalgorithm = \"SAC\" # the original\n";
    std::fs::write(&path, &spec).unwrap();
    let edited = dataset_spec::edit::with_reference_scores(&path, &scores).unwrap();
    let table = "[reference_scores]\nref_min_score = -12.5\nref_max_score = 3000.25\nnum_episodes_average_score = 100\n";
    let (head, train) = spec.split_once("\n[train]").unwrap();
    assert_eq!(edited, format!("{head}\n{table}\n[train]{train}"));
    // A table already there: its values replaced in place, their comments and places kept.
    let old = "[reference_scores]\n# measured\nref_min_score = 1.0 # random\nref_max_score = 2.0\nnum_episodes_average_score = 10\n";
    let spec = format!("{}\n{old}\n[train]{train}", head);
    std::fs::write(&path, &spec).unwrap();
    let edited = dataset_spec::edit::with_reference_scores(&path, &scores).unwrap();
    let new = "[reference_scores]\n# measured\nref_min_score = -12.5 # random\nref_max_score = 3000.25\nnum_episodes_average_score = 100\n";
    assert_eq!(edited, spec.replace(old, new));
    let read = dataset_spec::parse(&envspec::SourceFile::new(&path, edited)).unwrap();
    assert_eq!(read.reference_scores, Some(scores));
    // Scores that cannot be stored are refused, the file untouched.
    let same = RefScores {
        ref_max_score: -12.5,
        ..scores
    };
    let e = dataset_spec::edit::with_reference_scores(&path, &same).unwrap_err();
    assert_eq!(e.code, Code::E1801);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), spec);
}
