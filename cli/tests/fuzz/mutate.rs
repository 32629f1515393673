//! The input generator (a seeded SplitMix64) and the byte- and argv-level mutations.

use std::path::Path;

use super::ROOT;

/// SplitMix64: small, seedable, the same everywhere.
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn for_input(seed: u64, target: &str, i: u64) -> Rng {
        let h = target.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        Rng(seed ^ h ^ i.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    pub(super) fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    pub(super) fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

/// The dictionary (`tests/fuzz/dict.txt`): one token a line, `# ` comments, `\n \t \\ \u{..}`
/// escapes, and generated tokens.
pub(super) fn dictionary() -> Vec<Vec<u8>> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("tests/fuzz/dict.txt"))
        .expect("tests/fuzz/dict.txt");
    let mut out = vec![];
    for line in text.lines() {
        if line.is_empty() || line == "#" || line.starts_with("# ") {
            continue;
        }
        out.push(match line {
            "@LONG" => "a".repeat(70_000).into_bytes(),
            "@DEEP" => format!("{}{}", "[".repeat(5_000), "]".repeat(5_000)).into_bytes(),
            "@HUGE_INT" => format!("1{}", "0".repeat(400)).into_bytes(),
            _ => unescape(line).into_bytes(),
        });
    }
    out
}

fn unescape(s: &str) -> String {
    let mut out = String::new();
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match it.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('u') => {
                let hex: String = it.by_ref().skip(1).take_while(|&c| c != '}').collect();
                out.push(
                    u32::from_str_radix(&hex, 16)
                        .ok()
                        .and_then(char::from_u32)
                        .unwrap_or('?'),
                );
            }
            Some(c) => out.push(c),
            None => out.push('\\'),
        }
    }
    out
}

/// What a number of a spec or model becomes in the number mutation.
const NUMBERS: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "5e-324",
    "-1",
    "0",
    "-0",
    "999999999",
    "4294967296",
    "9223372036854775807",
    "1e9",
];

const INTERESTING: &[u8] = b"\0\xff\"'[]{}=,.\n<>/#\\:-";

fn is_word(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b"._-+$".contains(&b)
}

/// One to four stacked byte-level mutations of `data`; `others` are the same file of other seeds.
pub(super) fn mutate(rng: &mut Rng, data: &mut Vec<u8>, dict: &[Vec<u8>], others: &[Vec<u8>]) {
    for _ in 0..1 + rng.below(4) {
        let len = data.len();
        let at = rng.below(len + 1);
        match rng.below(14) {
            0 if len > 0 => data[at.min(len - 1)] ^= 1 << rng.below(8),
            1 if len > 0 => data[at.min(len - 1)] = *rng.pick(INTERESTING),
            2 => {
                let end = (at + 1 + rng.below(16)).min(len);
                data.drain(at..end);
            }
            3 => {
                let end = (at + 1 + rng.below(64)).min(len);
                let chunk = data[at..end].to_vec();
                let to = rng.below(len + 1);
                data.splice(to..to, chunk);
            }
            4 => {
                let t = rng.pick(dict).clone();
                data.splice(at..at, t);
            }
            // Replace the word (number, name, key) around `at` with a token: `0.01` → `nan`.
            5 | 6 => {
                let (mut s, mut e) = (at.min(len), at.min(len));
                while s > 0 && is_word(data[s - 1]) {
                    s -= 1;
                }
                while e < len && is_word(data[e]) {
                    e += 1;
                }
                let t = rng.pick(dict).clone();
                data.splice(s..e, t);
            }
            // Structure-aware: a token as an attribute of a random XML element (`<geom` →
            // `<geom size="-1"`), or as the value of a random `key = value` line.
            9 | 11 => {
                let tags: Vec<usize> = (0..len.saturating_sub(1))
                    .filter(|&k| data[k] == b'<' && data[k + 1].is_ascii_alphabetic())
                    .collect();
                let values: Vec<usize> = (0..len.saturating_sub(3))
                    .filter(|&k| &data[k..k + 3] == b" = ")
                    .collect();
                let t = rng.pick(dict).clone();
                if !tags.is_empty() {
                    let mut k = *rng.pick(&tags) + 1;
                    while k < len && is_word(data[k]) {
                        k += 1;
                    }
                    data.splice(k..k, b" ".iter().chain(&t).copied());
                } else if !values.is_empty() {
                    let k = *rng.pick(&values) + 3;
                    let e = data[k..]
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(len, |p| k + p);
                    data.splice(k..e, t);
                }
            }
            // A number of the input (a gain, a range bound, a size, a count) made extreme.
            12 | 13 => {
                let starts: Vec<usize> = (0..len)
                    .filter(|&k| {
                        data[k].is_ascii_digit() && (k == 0 || !is_word(data[k - 1]))
                            || data[k] == b'-' && data.get(k + 1).is_some_and(u8::is_ascii_digit)
                    })
                    .collect();
                if !starts.is_empty() {
                    let a = *rng.pick(&starts);
                    let mut e = a + 1;
                    while e < len && is_word(data[e]) {
                        e += 1;
                    }
                    data.splice(a..e, rng.pick(NUMBERS).bytes());
                }
            }
            // A random line copied elsewhere (a key or table twice, a row of a maze).
            10 => {
                let starts: Vec<usize> = std::iter::once(0)
                    .chain((0..len).filter(|&k| data[k] == b'\n').map(|k| k + 1))
                    .collect();
                let a = *rng.pick(&starts);
                let e = data[a..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(len, |p| a + p + 1);
                let line = data[a..e].to_vec();
                let to = *rng.pick(&starts);
                data.splice(to..to, line);
            }
            7 if !others.is_empty() => {
                let o = rng.pick(others);
                let s = rng.below(o.len() + 1);
                let e = (s + rng.below(256)).min(o.len());
                data.splice(at..at, o[s..e].iter().copied());
            }
            _ => data.truncate(at),
        }
    }
}

/// Argv-level mutations: replace, insert, remove, byte-mutate an argument, or splice seeds.
pub(super) fn mutate_args(
    rng: &mut Rng,
    args: &mut Vec<Vec<u8>>,
    dict: &[Vec<u8>],
    others: &[Vec<Vec<u8>>],
) {
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(args.len() + 1);
        match rng.below(6) {
            0 if at < args.len() => args[at] = rng.pick(dict).clone(),
            1 => args.insert(at, rng.pick(dict).clone()),
            2 if at < args.len() => {
                args.remove(at);
            }
            3 if at < args.len() => {
                let mut a = std::mem::take(&mut args[at]);
                mutate(rng, &mut a, dict, &[]);
                args[at] = a;
            }
            4 if !others.is_empty() => {
                let o = rng.pick(others);
                let from = rng.below(o.len() + 1);
                args.truncate(at);
                args.extend(o[from..].iter().cloned());
            }
            _ => {
                let t = rng.pick(dict).clone();
                args.insert(at, b"--set".to_vec());
                args.insert(at + 1, t);
            }
        }
    }
    // argv cannot carry NUL bytes.
    for a in args.iter_mut() {
        a.retain(|&b| b != 0);
    }
}
