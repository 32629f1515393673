//! The seed corpus (`tests/fuzz/corpus/`) and the inputs built from it.

use std::path::{Path, PathBuf};

use super::mutate::{Rng, mutate};
use super::{ROOT, Target};

pub(super) struct Seed {
    pub(super) dir: PathBuf,
    pub(super) name: String,
}

pub(super) fn seeds(t: &Target) -> Vec<Seed> {
    let dir = Path::new(ROOT).join("tests/fuzz/corpus").join(t.corpus);
    let mut out: Vec<Seed> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.file_name().is_some_and(|n| n != "world"))
        .map(|p| Seed {
            name: p.file_name().unwrap().to_string_lossy().into_owned(),
            dir: p,
        })
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

pub(super) fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        if e.path().is_file() {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

pub(super) fn fresh_dir(p: &Path) {
    let _ = std::fs::remove_dir_all(p);
    std::fs::create_dir_all(p).unwrap();
}

/// Build input `i` of a file target in `work`: a seed copied and one of its files mutated.
/// Returns a one-line description (seed, file).
pub(super) fn make_input(
    t: &Target,
    seeds: &[Seed],
    dict: &[Vec<u8>],
    rng: &mut Rng,
    work: &Path,
) -> String {
    let seed = rng.pick(seeds);
    fresh_dir(work);
    copy_dir(&seed.dir, work);
    let present: Vec<&str> = t
        .mutable
        .iter()
        .copied()
        .filter(|f| work.join(f).is_file())
        .collect();
    let file = *rng.pick(&present);
    let others: Vec<Vec<u8>> = seeds
        .iter()
        .filter_map(|s| std::fs::read(s.dir.join(file)).ok())
        .collect();
    let mut data = std::fs::read(work.join(file)).unwrap();
    mutate(rng, &mut data, dict, &others);
    std::fs::write(work.join(file), &data).unwrap();
    format!("seed {} file {file}", seed.name)
}
