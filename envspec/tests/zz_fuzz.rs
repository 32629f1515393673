// scratch, to be deleted
use envspec::{Spec, resolve};
use std::path::Path;
#[test]
fn fuzz() {
    let base = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../specs/gymnasium/ant.toml")).unwrap();
    let base = base.replace("../../assets", "/work/main/assets");
    let inserts = ["é", "€", "😀", "\"", "[", "]", "=", "\n", "{", "}", ",", "'", "\\", "\t", "#", "$", "!", ":", "-", "\r\n", "ü[", "\"é", "[é]"];
    let mut seed: u64 = 12345;
    let mut rnd = || { seed ^= seed << 13; seed ^= seed >> 7; seed ^= seed << 17; seed };
    let chars: Vec<(usize, char)> = base.char_indices().collect();
    let mut panics = 0; let mut n = 0;
    for _ in 0..4000 {
        let mut s = base.clone();
        for _ in 0..(1 + rnd() % 3) {
            let cs: Vec<usize> = s.char_indices().map(|(i, _)| i).collect();
            let pos = cs[(rnd() as usize) % cs.len()];
            let ins = inserts[(rnd() as usize) % inserts.len()];
            if rnd() % 3 == 0 {
                // delete a char
                let c = s[pos..].chars().next().unwrap();
                s.replace_range(pos..pos + c.len_utf8(), "");
            } else {
                s.insert_str(pos, ins);
            }
        }
        let _ = &chars;
        n += 1;
        let r = std::panic::catch_unwind(|| {
            match Spec::parse(Path::new("/tmp/envspec_docs_probe/fuzz.toml"), s.clone()) {
                Ok(spec) => match resolve(&spec, &[]) { Ok(_) => String::new(), Err(e) => e.to_string() },
                Err(e) => e.to_string(),
            }
        });
        if r.is_err() { panics += 1; if panics < 5 { println!("PANIC on:\n{s}\n-----"); } }
    }
    println!("{n} cases, {panics} panics");
}
