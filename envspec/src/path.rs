//! The one path normalizer, for paths written in specs (`xml_file`, `base`, `<include file>`)
//! joined onto the directory of the file that names them.

use std::path::{Component, Path, PathBuf};

/// Lexical normalization (the path may not exist yet; symlinks are not followed):
/// `.` components are dropped; `..` removes the normal component before it (`a/b/../c` → `a/c`);
/// a `..` with none before it is kept in a relative path (`../a` stays, it points outside the
/// start) and dropped right after the root (`/../a` → `/a`, as the OS resolves it).
pub fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.components().next_back() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                Some(Component::RootDir | Component::Prefix(_)) => {}
                Some(Component::ParentDir | Component::CurDir) | None => out.push(c),
            },
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::normalize;
    use std::path::Path;

    #[test]
    fn the_documented_rule() {
        for (from, to) in [
            ("specs/gymnasium/../../assets/ant.xml", "assets/ant.xml"),
            ("./a/./b/../c", "a/c"),
            ("../a", "../a"),
            ("a/../../b", "../b"),
            ("../../a/b/..", "../../a"),
            ("/x/y/../z", "/x/z"),
            ("/../a", "/a"),
            ("a/..", ""),
        ] {
            assert_eq!(normalize(Path::new(from)), Path::new(to), "{from}");
        }
    }
}

/// `${NAME}` in a path replaced by the environment variable's value (a model installed by a
/// Python package, found through a variable the user sets). `Err` names a variable that is unset
/// or not valid Unicode; a `$` not followed by `{NAME}` stays as it is.
pub fn expand_env(s: &str) -> Result<String, String> {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find("${") {
        let Some(len) = rest[i + 2..].find('}') else {
            break;
        };
        let name = &rest[i + 2..i + 2 + len];
        out.push_str(&rest[..i]);
        let value = match name.strip_prefix("python:") {
            Some(package) => python_package_dir(package).map(|p| p.to_string_lossy().into_owned()),
            None => std::env::var(name).ok(),
        };
        match value {
            Some(v) => out.push_str(&v),
            None => return Err(name.to_string()),
        }
        rest = &rest[i + 3 + len..];
    }
    out.push_str(rest);
    Ok(out)
}

/// The directory of the installed Python package `name` (`${python:name}`): the first entry of
/// `ENVC_PYTHON_PATH`, then `PYTHONPATH`, then the `sys.path` of `python3` (the envc package
/// sets `ENVC_PYTHON_PATH` to its own interpreter's `sys.path` when imported) holding
/// `name/__init__.py`. Found by hand: no crate asks an interpreter for its search path.
pub fn python_package_dir(name: &str) -> Option<PathBuf> {
    let valid = !name.is_empty()
        && name
            .split('.')
            .all(|p| !p.is_empty() && p.chars().all(|c| c.is_alphanumeric() || c == '_'));
    if !valid {
        return None;
    }
    let rel: PathBuf = name.split('.').collect();
    let find = |dirs: &mut dyn Iterator<Item = PathBuf>| {
        dirs.map(|d| d.join(&rel))
            .find(|p| p.join("__init__.py").is_file())
            .and_then(|p| std::path::absolute(p).ok())
    };
    for var in ["ENVC_PYTHON_PATH", "PYTHONPATH"] {
        if let Some(v) = std::env::var_os(var)
            && let Some(p) = find(&mut std::env::split_paths(&v))
        {
            return Some(p);
        }
    }
    let out = std::process::Command::new("python3")
        .args(["-c", "import sys; print('\\n'.join(sys.path))"])
        .stderr(std::process::Stdio::null())
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    find(&mut text.lines().filter(|l| !l.is_empty()).map(PathBuf::from))
}

#[cfg(test)]
mod env_tests {
    use super::expand_env;

    #[test]
    fn variables_expand_and_unset_ones_are_named() {
        // (a variable every test process has, so the test sets none)
        let path = std::env::var("PATH").unwrap_or_default();
        assert_eq!(
            expand_env("${PATH}/arm.xml").unwrap(),
            format!("{path}/arm.xml")
        );
        assert_eq!(expand_env("a/$b/c.xml").unwrap(), "a/$b/c.xml");
        assert_eq!(
            expand_env("${ENVC_TEST_NOT_SET_ANYWHERE}/x").unwrap_err(),
            "ENVC_TEST_NOT_SET_ANYWHERE"
        );
    }
}
