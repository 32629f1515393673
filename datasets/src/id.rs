//! Minari dataset ids: `(namespace/)name-vN`, exactly the ids Minari 0.5.4 parses (its regex
//! `^(?:([-_\w][-_\w/]*[-_\w]+)/)?([-_\w]+?)(?:-v(\d+))?$`, with the version required because
//! `parse_dataset_id` needs it), a little stricter where Minari's leniency breaks paths: no empty
//! namespace levels and no leading zeros in the version (Minari would regenerate `-v1` from `-v01`
//! and the directory would no longer match the id).

use crate::error::DatasetError;

/// A parsed dataset id.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DatasetId {
    /// `None` or the levels joined by `/` (e.g. `mujoco/ant`).
    pub namespace: Option<String>,
    /// The name, before `-vN`.
    pub name: String,
    /// N of `-vN`.
    pub version: u64,
}

fn word(c: char) -> bool {
    c == '-' || c == '_' || c.is_alphanumeric()
}

impl DatasetId {
    /// Parse an id as Minari does, a little stricter (see the module docs; E1201).
    pub fn parse(id: &str) -> Result<DatasetId, DatasetError> {
        let bad = |why: &str| DatasetError::BadId {
            id: id.to_string(),
            why: why.to_string(),
        };
        let (namespace, rest) = match id.rfind('/') {
            Some(i) => (Some(&id[..i]), &id[i + 1..]),
            None => (None, id),
        };
        if let Some(ns) = namespace {
            if ns.chars().count() < 2 {
                return Err(bad(
                    "the namespace must be at least 2 characters (Minari's rule)",
                ));
            }
            if ns.split('/').any(|level| level.is_empty()) {
                return Err(bad("empty namespace level"));
            }
            if !ns.chars().all(|c| c == '/' || word(c)) {
                return Err(bad(
                    "namespaces may use letters, digits, `_`, `-` and `/` only",
                ));
            }
        }
        let Some(v) = rest.rfind("-v") else {
            return Err(bad(
                "expected `name-vN` (the version is required, e.g. `-v0`)",
            ));
        };
        let (name, digits) = (&rest[..v], &rest[v + 2..]);
        if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
            return Err(bad("expected `name-vN` with a decimal version, e.g. `-v0`"));
        }
        if digits.len() > 1 && digits.starts_with('0') {
            return Err(bad(
                "the version has a leading zero (Minari would rename it)",
            ));
        }
        let version = digits
            .parse::<u64>()
            .map_err(|_| bad("the version is too large"))?;
        if name.is_empty() || !name.chars().all(word) {
            return Err(bad(
                "the name must be non-empty and use letters, digits, `_` and `-` only",
            ));
        }
        Ok(DatasetId {
            namespace: namespace.map(str::to_string),
            name: name.to_string(),
            version,
        })
    }

    /// The id as Minari writes it (`gen_dataset_id`).
    pub fn as_string(&self) -> String {
        match &self.namespace {
            Some(ns) => format!("{ns}/{}-v{}", self.name, self.version),
            None => format!("{}-v{}", self.name, self.version),
        }
    }

    /// The namespace levels, outermost first: `a/b` gives `["a", "a/b"]`.
    pub fn namespace_levels(&self) -> Vec<String> {
        let mut out = vec![];
        if let Some(ns) = &self.namespace {
            let mut acc = String::new();
            for level in ns.split('/') {
                if !acc.is_empty() {
                    acc.push('/');
                }
                acc.push_str(level);
                out.push(acc.clone());
            }
        }
        out
    }
}

impl std::fmt::Display for DatasetId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.as_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids() {
        let ok = DatasetId::parse("mujoco/ant/expert-v0").unwrap();
        assert_eq!(ok.namespace.as_deref(), Some("mujoco/ant"));
        assert_eq!((ok.name.as_str(), ok.version), ("expert", 0));
        assert_eq!(ok.namespace_levels(), ["mujoco", "mujoco/ant"]);
        let lazy = DatasetId::parse("ns/x-y-v0-v1").unwrap();
        assert_eq!((lazy.name.as_str(), lazy.version), ("x-y-v0", 1));
        assert!(DatasetId::parse("plain-v3").is_ok());
        for bad in [
            "a/x-v0",
            "human",
            "x-v",
            "ns/a.b-v0",
            "a b-v0",
            "ns//x-v0",
            "/x-v0",
            "ns/x-v01",
            "ns/-v0",
            "../x-v0",
            "ns/x-v0/",
        ] {
            assert!(DatasetId::parse(bad).is_err(), "{bad} accepted");
        }
    }
}
