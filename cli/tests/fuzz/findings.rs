//! Findings: recognised as known problems or saved with their input files, a few per signature.

use std::path::{Path, PathBuf};

use super::corpus::{copy_dir, fresh_dir};
use super::{KEEP_PER_SIGNATURE, KNOWN};

pub(super) struct Finding {
    pub(super) symptom: String,
    /// What groups findings of one cause: the panic location, the signal, "timeout".
    pub(super) signature: String,
    pub(super) detail: String,
}

pub(super) struct Findings {
    dir: PathBuf,
    pub(super) saved: std::collections::BTreeMap<String, usize>,
    pub(super) known: usize,
    pub(super) new: Vec<String>,
}

impl Findings {
    pub(super) fn new(dir: PathBuf) -> Findings {
        Findings {
            dir,
            saved: Default::default(),
            known: 0,
            new: vec![],
        }
    }
    /// Record a finding; its input files are copied from `work`.
    pub(super) fn add(&mut self, target: &str, i: u64, what: &str, work: &Path, f: Finding) {
        // Known problems are recognised by the symptom, the output and the input files' text.
        let mut text = format!("{}\n{}\n{}", f.symptom, f.detail, what);
        for e in std::fs::read_dir(work).into_iter().flatten().flatten() {
            let b = std::fs::read(e.path()).unwrap_or_default();
            text += &String::from_utf8_lossy(&b[..b.len().min(100_000)]);
        }
        let symptom = format!("{} {}", f.symptom, f.signature);
        let known = KNOWN
            .iter()
            .find(|(s, k, _)| symptom.contains(s) && text.contains(k));
        if let Some((_, _, why)) = known {
            self.known += 1;
            eprintln!("fuzz {target} #{i}: known ({why}): {}", f.symptom);
        }
        let n = self.saved.entry(f.signature.clone()).or_default();
        *n += 1;
        if known.is_none() && *n == 1 {
            self.new
                .push(format!("{target} #{i}: {} [{}]", f.symptom, f.signature));
        }
        if *n > KEEP_PER_SIGNATURE {
            return;
        }
        let dir = self.dir.join(format!("{target}-{i}"));
        fresh_dir(&dir);
        copy_dir(work, &dir);
        std::fs::write(
            dir.join("finding.txt"),
            format!(
                "target: {target}\ninput: {i}\n{what}\nsymptom: {}\nsignature: {}\n\n{}\n",
                f.symptom, f.signature, f.detail
            ),
        )
        .unwrap();
    }
}
