//! The one reader records what a spec pulls in (`envspec::source`): a task spec and its model,
//! a multi-agent spec, its base chain and the base's model, in the order read.

use std::path::{Path, PathBuf};

use envspec::source::Reader;

/// What `env!` and `multi_agent_env!` track: every file the spec pulls in, in the order read.
#[test]
fn loading_a_spec_records_the_spec_its_base_and_its_model() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let paths = |r: &Reader| -> Vec<PathBuf> {
        r.files()
            .iter()
            .map(|f| envspec::path::normalize(&f.path))
            .collect()
    };
    let mut reader = Reader::disk();
    let task = root.join("specs/gymnasium/hopper.toml");
    reader.run(|| envspec::load(&task, &[])).unwrap();
    let model = envspec::path::normalize(&root.join("assets/gymnasium/hopper.xml"));
    assert_eq!(
        paths(&reader),
        vec![envspec::path::normalize(&task), model.clone()]
    );
    assert!(reader.files().iter().all(|f| f.hash.is_some()));

    let mut reader = Reader::disk();
    let agents = root.join("specs/mamujoco/hopper.toml");
    reader
        .run(|| envspec::multi_agent::load(&agents, &[]))
        .unwrap();
    // The base chain is read first (its check), then the base spec is loaded.
    assert_eq!(
        paths(&reader),
        vec![
            envspec::path::normalize(&agents),
            envspec::path::normalize(&task),
            model
        ]
    );
}
