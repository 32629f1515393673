//! The maze grid with the location of every cell, and the layout checks: rows of one length
//! (E0701), known cells (E0702), a goal and a reset candidate (E0703, E0704), every goal
//! reachable from a reset cell (E0705).

use std::collections::VecDeque;

use super::{Cell, candidates};
use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location};
use crate::value::{Val, ValKind};

const CELLS: &str = "1 (wall), 0 (free), r (reset), g (goal), c (reset and goal)";

/// A grid as written: each cell with its location, each row with the span of its cells.
pub(super) struct Grid {
    pub cells: Vec<Vec<(Cell, Location)>>,
    pub row_locs: Vec<Location>,
}

impl Grid {
    pub fn cells(&self) -> Vec<Vec<Cell>> {
        self.cells
            .iter()
            .map(|r| r.iter().map(|(c, _)| *c).collect())
            .collect()
    }
}

fn cell(tok: &str, loc: &Location, d: &mut Diagnostics) -> Option<Cell> {
    Some(match tok {
        "1" => Cell::Wall,
        "0" => Cell::Free,
        "r" => Cell::Reset,
        "g" => Cell::Goal,
        "c" => Cell::Combined,
        _ => {
            let lower = tok.to_lowercase();
            let help = if ["r", "g", "c"].contains(&lower.as_str()) {
                format!("cells are lowercase: did you mean `{lower}`?")
            } else if tok.len() > 1 && tok.chars().all(|c| "10rgc".contains(c)) {
                let spaced: Vec<String> = tok.chars().map(String::from).collect();
                format!(
                    "separate cells with spaces: `{}`; a cell is one of {CELLS}",
                    spaced.join(" ")
                )
            } else {
                format!("a cell is one of {CELLS}")
            };
            d.push(
                Diagnostic::new(Code::E0702, format!("unknown maze cell `{tok}`"))
                    .at(loc.clone())
                    .label("expected 1, 0, r, g or c")
                    .help(help),
            );
            return None;
        }
    })
}

/// Read a grid: a string of rows (one per line, cells separated by whitespace) or an array of
/// rows, each a string or an array of `1`/`0`/`"r"`/`"g"`/`"c"`. Unknown cells are E0702; rows
/// of different lengths E0701. None after any error.
pub(super) fn read_grid(v: &Val, d: &mut Diagnostics) -> Option<Grid> {
    let before = d.len();
    let mut g = Grid {
        cells: vec![],
        row_locs: vec![],
    };
    match &v.kind {
        ValKind::Str(s) => {
            let offsets = string_offsets(&v.loc, s);
            let mut start = 0;
            for line in s.split('\n') {
                let toks = tokens(line, start);
                start += line.len() + 1;
                if toks.is_empty() {
                    continue;
                }
                let at = |a: usize, b: usize| match &offsets {
                    Some(o) => Location::new(&v.loc.file, o[a]..o[b - 1] + 1),
                    None => v.loc.clone(),
                };
                let (first, last) = (toks[0].1, toks[toks.len() - 1].2);
                g.row_locs.push(at(first, last));
                let row = toks
                    .iter()
                    .filter_map(|&(t, a, b)| cell(t, &at(a, b), d).map(|c| (c, at(a, b))))
                    .collect();
                g.cells.push(row);
            }
        }
        ValKind::Array(rows) => {
            for r in rows {
                let row = match &r.kind {
                    ValKind::Str(s) => {
                        let o = string_offsets(&r.loc, s);
                        tokens(s, 0)
                            .into_iter()
                            .filter_map(|(t, a, b)| {
                                let at = match &o {
                                    Some(o) => Location::new(&r.loc.file, o[a]..o[b - 1] + 1),
                                    None => r.loc.clone(),
                                };
                                cell(t, &at, d).map(|c| (c, at))
                            })
                            .collect()
                    }
                    ValKind::Array(a) => a
                        .iter()
                        .filter_map(|c| {
                            let tok = match &c.kind {
                                ValKind::Int(i) => i.to_string(),
                                ValKind::Str(s) => s.clone(),
                                _ => {
                                    d.push(
                                        c.type_error("a maze cell", "1, 0, \"r\", \"g\" or \"c\""),
                                    );
                                    return None;
                                }
                            };
                            cell(&tok, &c.loc, d).map(|x| (x, c.loc.clone()))
                        })
                        .collect(),
                    _ => {
                        d.push(r.type_error("a maze row", "a string or an array of cells"));
                        vec![]
                    }
                };
                g.row_locs.push(r.loc.clone());
                g.cells.push(row);
            }
        }
        _ => {
            d.push(v.type_error(
                "`map`",
                "a grid (a string of rows or an array of rows) or a map file path",
            ));
        }
    }
    if d.len() > before {
        return None;
    }
    let width = g.cells.first().map_or(0, Vec::len);
    for (i, row) in g.cells.iter().enumerate().skip(1) {
        if row.len() != width {
            d.push(
                Diagnostic::new(
                    Code::E0701,
                    format!(
                        "maze row {i} has {} but row 0 has {width}",
                        cells(row.len())
                    ),
                )
                .at(g.row_locs[i].clone())
                .label(format!("expected {}", cells(width)))
                .help("every row of a maze has the same number of cells (walls are `1`)"),
            );
        }
    }
    (d.len() == before).then_some(g)
}

/// `1 cell`, `3 cells`.
fn cells(n: usize) -> String {
    format!("{n} cell{}", if n == 1 { "" } else { "s" })
}

/// Whitespace-separated tokens of `line` with their byte ranges (offset by `base`).
fn tokens(line: &str, base: usize) -> Vec<(&str, usize, usize)> {
    let mut out = vec![];
    let mut start = None;
    for (i, c) in line
        .char_indices()
        .chain(std::iter::once((line.len(), ' ')))
    {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                out.push((&line[s..i], base + s, base + i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    out
}

/// The source offset of every byte of a string value's text, plus one past its end: TOML
/// strings may hold escapes (`"1 1\n1 g"`) and multi-line strings drop their first newline, so
/// positions in the text are not positions in the file. None when the literal cannot be mapped
/// (callers then point at the whole value).
fn string_offsets(loc: &Location, text: &str) -> Option<Vec<usize>> {
    let raw = loc.file.text.get(loc.span.clone())?;
    if raw == text {
        // A bare string (an override's text that is not a TOML literal).
        return Some((loc.span.start..=loc.span.end).collect());
    }
    let delim = ["\"\"\"", "'''", "\"", "'"]
        .into_iter()
        .find(|q| raw.starts_with(q) && raw.len() >= 2 * q.len() && raw.ends_with(q))?;
    let (literal, multi) = (delim.starts_with('\''), delim.len() == 3);
    let end = raw.len() - delim.len();
    let mut i = delim.len();
    if multi {
        i += [("\r\n", 2), ("\n", 1)]
            .into_iter()
            .find(|(nl, _)| raw[i..].starts_with(nl))
            .map_or(0, |(_, n)| n);
    }
    let (base, bytes) = (loc.span.start, raw.as_bytes());
    let (mut out, mut decoded) = (Vec::with_capacity(text.len() + 1), String::new());
    while i < end {
        let (ch, len) = if !literal && bytes[i] == b'\\' {
            let hex = |n: usize| {
                let h = raw.get(i + 2..i + 2 + n)?;
                Some((char::from_u32(u32::from_str_radix(h, 16).ok()?)?, 2 + n))
            };
            match *bytes.get(i + 1)? {
                b'n' => ('\n', 2),
                b't' => ('\t', 2),
                b'r' => ('\r', 2),
                b'b' => ('\u{8}', 2),
                b'f' => ('\u{c}', 2),
                b'e' => ('\u{1b}', 2),
                b'"' => ('"', 2),
                b'\\' => ('\\', 2),
                b'x' => hex(2)?,
                b'u' => hex(4)?,
                b'U' => hex(8)?,
                c if multi && (c as char).is_whitespace() => {
                    // A line-ending backslash drops all whitespace up to the next text.
                    let skip = raw[i + 1..end]
                        .find(|c: char| !c.is_whitespace())
                        .unwrap_or(end - i - 1);
                    i += 1 + skip;
                    continue;
                }
                _ => return None,
            }
        } else {
            let ch = raw[i..].chars().next()?;
            (ch, ch.len_utf8())
        };
        // Byte k of a character maps to byte k of its source, so a span ending after a cell's
        // last byte ends on a character boundary (an escape is at least as long as its UTF-8).
        out.extend((0..ch.len_utf8()).map(|k| base + i + k));
        decoded.push(ch);
        i += len;
    }
    out.push(base + end);
    (decoded == text).then_some(out)
}

/// E0703–E0705 on a well-formed grid. `map` is where the map was given (for whole-map errors).
pub(super) fn check_layout(g: &Grid, map: &Location, d: &mut Diagnostics) {
    let grid = g.cells();
    let (goals, resets) = candidates(&grid);
    let none = |code, what: &str, letter: &str| {
        Diagnostic::new(code, format!("the maze has no {what} cell"))
            .at(map.clone())
            .label(format!(
                "expected {} `{letter}` or `c` cell, or a free `0` cell",
                if letter == "r" { "an" } else { "a" }
            ))
            .help(format!(
                "mark one with `{letter}` (or `c`); without any, the free `0` cells are {what} cells, as in Gymnasium-Robotics"
            ))
    };
    if goals.is_empty() {
        d.push(none(Code::E0703, "goal", "g"));
    }
    if resets.is_empty() {
        d.push(none(Code::E0704, "reset", "r"));
    }
    if goals.is_empty() || resets.is_empty() {
        return;
    }
    // Regions of free cells, 4-connected: two free cells touching only at a corner are separated
    // by the two wall blocks that meet there, which leave no gap.
    let (rows, cols) = (grid.len(), grid[0].len());
    let mut region = vec![vec![usize::MAX; cols]; rows];
    let mut n = 0;
    for i in 0..rows {
        for j in 0..cols {
            if grid[i][j] == Cell::Wall || region[i][j] != usize::MAX {
                continue;
            }
            let mut queue = VecDeque::from([(i, j)]);
            region[i][j] = n;
            while let Some((a, b)) = queue.pop_front() {
                let next = [
                    (a.wrapping_sub(1), b),
                    (a + 1, b),
                    (a, b.wrapping_sub(1)),
                    (a, b + 1),
                ];
                for (x, y) in next {
                    if x < rows
                        && y < cols
                        && grid[x][y] != Cell::Wall
                        && region[x][y] == usize::MAX
                    {
                        region[x][y] = n;
                        queue.push_back((x, y));
                    }
                }
            }
            n += 1;
        }
    }
    // The reset draw skips cells within 0.5·s of the (noisy) goal, so a reset cell never starts
    // an episode in the goal's own cell: a goal needs a reset cell elsewhere in its region.
    let cut_off: Vec<[usize; 2]> = goals
        .iter()
        .filter(|&&[i, j]| {
            !resets
                .iter()
                .any(|&[a, b]| region[a][b] == region[i][j] && [a, b] != [i, j])
        })
        .copied()
        .collect();
    if let Some(&[i, j]) = cut_off.first() {
        let more = match cut_off.len() - 1 {
            0 => String::new(),
            k => format!(" (and {k} more goal cell{})", if k == 1 { "" } else { "s" }),
        };
        d.push(
            Diagnostic::new(
                Code::E0705,
                format!("goal cell (row {i}, col {j}) cannot be reached from any reset cell{more}"),
            )
            .at(g.cells[i][j].1.clone())
            .label("no reset cell in this cell's part of the maze")
            .help("open a path of free cells to a reset cell (moves are up, down, left, right: walls meeting at a corner close it)"),
        );
    }
}
