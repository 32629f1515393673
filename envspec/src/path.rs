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
