//! envc's limits, in one place: how large a file, a MuJoCo size, a `frame_skip` or an episode may
//! be before envc refuses it (E0110) instead of hanging, aborting or exhausting memory. Every
//! bound is far above what any published environment uses; `docs/limits.md` lists them with the
//! reasons.

use std::io::Read;
use std::path::Path;

use crate::diagnostic::{Code, Diagnostic, Location, SourceFile};

/// A spec, map, registry or agents file (the largest bundled spec is about 10 KB).
pub const MAX_SPEC_BYTES: u64 = 4 << 20;
/// One MJCF or URDF file, each `<include>` counted separately (Menagerie's largest is ~1 MB).
pub const MAX_MODEL_BYTES: u64 = 64 << 20;
/// A mesh, texture, heightfield or skin file a model names (read by MuJoCo, not by envspec).
pub const MAX_ASSET_BYTES: u64 = 512 << 20;
/// Physics steps per env step (Gymnasium's largest is 5).
pub const MAX_FRAME_SKIP: i64 = 1000;
/// Steps per episode (Gymnasium's largest is 1000). 0 means no time limit.
pub const MAX_EPISODE_STEPS: i64 = 10_000_000;
/// Episodes of one `envc run`, `envc collect` or `envc.collect`: each one's return and length
/// are kept for the summary or the dataset's metadata.
pub const MAX_EPISODES: u64 = 10_000_000;
/// Steps of a dataset spec's `steps` budget (Minari's largest MuJoCo datasets hold 1–2 million).
pub const MAX_DATASET_STEPS: u64 = 1_000_000_000;
/// A trajectory `envc rollout` holds in memory before writing it (observations, actions, rewards
/// and info, 8 bytes a number): about a million Humanoid steps.
pub const MAX_TRAJECTORY_BYTES: u64 = 4 << 30;
/// Draws one `resample_until` may take at reset before it gives up (E1104). Gymnasium loops for
/// ever; Reacher's goal is accepted with probability π/4, so a real spec never gets near this.
pub const MAX_RESAMPLE_DRAWS: u32 = 1_000_000;
/// Times a reset starts over because a `settle` step's check failed (each restart runs the
/// settling physics again); beyond it the reset fails with E1104.
pub const MAX_SETTLE_RESTARTS: u32 = 1_000;
/// MuJoCo sizes a model states in its MJCF, checked before MuJoCo allocates them: an absurd
/// `nuser_geom` or texture size otherwise makes MuJoCo allocate gigabytes (or throw
/// `std::bad_alloc`, caught by `runtime/csrc/mujoco_catch.cc` as E1001).
pub const MAX_ARENA_BYTES: u64 = 4 << 30;
/// Each `nuser_*` (user numbers per element), `nkey`.
pub const MAX_PER_ELEMENT: i64 = 100_000;
/// `nuserdata`, `nconmax`, `njmax`, `nstack` (entries, not bytes).
pub const MAX_BUFFER_ENTRIES: i64 = 100_000_000;
/// Texture pixels (width × height), heightfield samples (nrow × ncol), replicated copies and
/// composite/flexcomp elements.
pub const MAX_GRID: i64 = 100_000_000;
/// MuJoCo's `<option timestep>`, in seconds (Gymnasium's largest is 0.01; MuJoCo's default 0.002).
pub const MAX_TIMESTEP: f64 = 1.0;
/// A maze's `maze_size_scaling`, `maze_height` and `position_noise_range` (the reference's are
/// at most 4): beyond, the walls leave `MAX_COORDINATE` or the goal noise draw overflows.
pub const MAX_MAZE_SCALE: f64 = 1000.0;
/// Model coordinates (qpos0, body and geom positions, geom sizes), in metres or radians: beyond
/// this MuJoCo's collision and integration take seconds per step or reset the state.
pub const MAX_COORDINATE: f64 = 1e6;
/// Command ranges, `[actions]` gains, scales and ranges, and event draws and pushes: like reset
/// draws, a value beyond this makes the simulation diverge within a step (`kp = 1e308` gave NaN
/// accelerations, a command range of ±1e308 overflowed numpy's `uniform`).
pub const MAX_MAGNITUDE: f64 = 1e6;
/// A reset draw that moves a position further than this (metres) is warning W0171: a robot's
/// workspace is a few metres, so 15 is centimetres written for metres.
pub const PLAUSIBLE_DISTANCE: f64 = 10.0;
/// The largest `dim` of a `<user>` sensor envspec numbers (`sensordata[...]`); a larger one
/// is MuJoCo's to check, and `sensordata` cannot select past it.
pub const MAX_SENSOR_DIM: usize = 10_000;
/// Physics steps `[init]` may run when an env is made (`settle_steps × frame_skip`): every env
/// of a vector env runs them.
pub const MAX_SETTLE_PHYSICS_STEPS: u64 = 100_000;
/// The most solver, line-search, no-slip or collision iterations `[physics]` may ask for per
/// physics step (MuJoCo's defaults are 100, 50, 0 and 35; mjlab's rough tasks use 500). At
/// 10,000 a step of a contact-rich model took 1–8 s; the cap is 10 × mjlab's largest.
pub const MAX_SOLVER_ITERATIONS: u32 = 1_000;
/// Envs in one vector env (each holds its own `mjData`; the memory they need is checked too).
pub const MAX_VEC_ENVS: usize = 100_000;
/// Observation delay and action latency, in env steps: each env keeps that many past values of
/// the segment (or action) for the whole run.
pub const MAX_DELAY_STEPS: i64 = 10_000;
/// Elements nested in one MJCF or URDF file (`<body>`, `<frame>`, `<default>`, anything), and
/// the depth of a URDF's link chain: the readers recurse per level (10,000 nested bodies
/// overflowed the stack) and MuJoCo's own reader stops near 1,000. Menagerie's deepest models
/// nest about 20 levels.
pub const MAX_NESTING: usize = 500;
/// MJCF `<include>`s nested in one another (no bundled model includes another). A file that
/// includes itself, directly or not, is a cycle, reported as such at the `<include>` that closes
/// it ([`include_cycle`]) wherever it is read: from the disk, at a git revision, in codegen.
pub const MAX_INCLUDE_DEPTH: usize = 32;
/// Bodies in one model (MJCF bodies or URDF links): MuJoCo's compile time grows with the square
/// of the body count (0.18 s at 2,000 bodies, 13.6 s at 16,000, over 120 s at 50,000). At this
/// limit a compile takes about a second; the largest bundled model has 17 bodies.
pub const MAX_BODIES: usize = 5_000;
/// Tiles of a `[terrain]` grid (mjlab's rough grid has 200): each adds up to ~100 geoms, and
/// MuJoCo's collision broad phase grows with them.
pub const MAX_TERRAIN_TILES: usize = 2_000;
/// Heightfield cells of one `[terrain]` in all (a 10 × 20 grid of 8 m tiles at 0.1 m is 1.28 M):
/// memory for the model and its copies.
pub const MAX_TERRAIN_CELLS: usize = 20_000_000;
/// Geoms in a model with its `[terrain]` (the model's own, the spec's, the terrain's boxes,
/// heightfields and borders): MuJoCo's compile time grows with the square of the geom count
/// (90,000 stairs boxes took 14–17 s).
pub const MAX_GEOMS: usize = 20_000;
/// Height levels of a heightfield tile (a height over `vertical_scale`, and the count of
/// `random_uniform`'s steps): the heights are integers, as mjlab's, so a tiny scale saturated them
/// and a tiny step asked for billions of levels (mjlab's rough tiles have at most 800).
pub const MAX_TERRAIN_LEVELS: f64 = 1e6;
/// An observation noise's amplitude (`level × scale`), like reset draws: noise beyond it would
/// drown every observation or overflow.
pub const MAX_NOISE: f64 = 1e6;

/// Entries (files and directories) one registered spec directory may hold in all, and how deep
/// it may nest: `register("/proc/self")` walked the whole file system.
pub const MAX_SPEC_DIR_ENTRIES: usize = 100_000;
/// Directories nested in one registered spec directory.
pub const MAX_SPEC_DIR_DEPTH: usize = 32;
/// A power a reward term raises a speed to (`feet_clearance power`): 100 m/s to the 16th is
/// 1e32; 1e308 turned every return into -inf.
pub const MAX_EXPONENT: f64 = 16.0;

/// Why a file could not be read.
#[derive(Debug)]
pub enum ReadError {
    /// The operating system's error (missing file, no permission, ...).
    Io(std::io::Error),
    /// A device, FIFO, socket or directory: reading it could block or never end.
    NotAFile(&'static str),
    /// Larger than the limit for its kind of file.
    TooLarge {
        /// The limit in bytes.
        limit: u64,
    },
    /// Not UTF-8: the byte offset of the first invalid byte.
    NotUtf8 {
        /// Byte offset of the first invalid byte.
        offset: usize,
    },
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::Io(e) => write!(f, "{e}"),
            ReadError::NotAFile(kind) => write!(f, "it is a {kind}, not a regular file"),
            ReadError::TooLarge { limit } => write!(
                f,
                "it is larger than envc's limit of {} (envspec::limits)",
                human_bytes(*limit)
            ),
            ReadError::NotUtf8 { offset } => {
                write!(f, "it is not UTF-8 text (invalid byte at offset {offset})")
            }
        }
    }
}

impl ReadError {
    /// E0110 for a size limit, else the caller's code for an unreadable file.
    pub fn code(&self, unreadable: Code) -> Code {
        match self {
            ReadError::TooLarge { .. } => Code::E0110,
            _ => unreadable,
        }
    }
}

/// `4 MiB`, `512 MiB`, `4 GiB`.
pub fn human_bytes(n: u64) -> String {
    match n {
        n if n >= 10 << 30 && n % (1 << 30) != 0 => format!("{} GiB", n >> 30),
        n if n >= 1 << 30 && n % (1 << 30) == 0 => format!("{} GiB", n >> 30),
        n if n >= 1 << 20 && n % (1 << 20) == 0 => format!("{} MiB", n >> 20),
        n => format!("{n} bytes"),
    }
}

/// The kind of a non-regular file, or None for a regular file.
fn not_a_file(meta: &std::fs::Metadata) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    match () {
        _ if t.is_file() => None,
        _ if t.is_dir() => Some("directory"),
        _ if t.is_char_device() || t.is_block_device() => Some("device"),
        _ if t.is_fifo() => Some("FIFO"),
        _ if t.is_socket() => Some("socket"),
        _ => Some("special file"),
    }
}

/// Check that `path` is a regular file of at most `limit` bytes, without opening it (opening a
/// FIFO blocks until a writer comes).
pub fn check_file(path: &Path, limit: u64) -> Result<(), ReadError> {
    let meta = std::fs::metadata(path).map_err(ReadError::Io)?;
    if let Some(kind) = not_a_file(&meta) {
        return Err(ReadError::NotAFile(kind));
    }
    if meta.len() > limit {
        return Err(ReadError::TooLarge { limit });
    }
    Ok(())
}

/// Read a text file of at most `limit` bytes. The read itself is bounded too, so a file that
/// grows while it is read cannot exhaust memory.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    check_file(path, limit)?;
    let mut bytes = vec![];
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(ReadError::Io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit });
    }
    String::from_utf8(bytes).map_err(|e| ReadError::NotUtf8 {
        offset: e.utf8_error().valid_up_to(),
    })
}

/// The sizes an MJCF document states that make MuJoCo allocate: `<size>`'s user and buffer
/// sizes and `memory`, texture and heightfield grids, replicate and composite counts. Each one
/// over its limit is an E0110 at its attribute. Also `<option>`'s numbers: finite, with a
/// timestep in (0, `MAX_TIMESTEP`] (E0105). `source` is the document's text as a located file.
pub fn check_mjcf_sizes(
    doc: &roxmltree::Document,
    source: &std::sync::Arc<SourceFile>,
) -> Vec<Diagnostic> {
    let mut out = vec![];
    for node in doc.descendants().filter(|n| n.is_element()) {
        match node.tag_name().name() {
            "option" => option_numbers(node, source, &mut out),
            "size" => stated_sizes(node, source, &mut out),
            tag @ ("texture" | "hfield") => grid_samples(node, tag, source, &mut out),
            tag @ ("replicate" | "composite" | "flexcomp") => {
                copy_count(node, tag, source, &mut out)
            }
            _ => {}
        }
    }
    out
}

/// Where `attr` of `node` is in `source` (the element itself when it has no such attribute).
fn attr_at(source: &std::sync::Arc<SourceFile>, node: roxmltree::Node, attr: &str) -> Location {
    let span = node
        .attribute_node(attr)
        .map(|a| a.range_value())
        .unwrap_or_else(|| node.range());
    Location::new(source, span)
}

/// An integer attribute (MuJoCo reads ints with strtol; a non-number is MuJoCo's to report).
fn int_attr(node: roxmltree::Node, attr: &str) -> Option<i64> {
    node.attribute(attr)?
        .trim()
        .parse::<f64>()
        .ok()
        .map(|x| x as i64)
}

/// E0110 at `attr` of `node`: it asks MuJoCo for `value`, beyond `limit`.
fn over(
    source: &std::sync::Arc<SourceFile>,
    node: roxmltree::Node,
    attr: &str,
    value: String,
    limit: String,
) -> Diagnostic {
    Diagnostic::new(
        Code::E0110,
        format!(
            "<{} {attr}> asks MuJoCo for {value}, beyond envc's limit of {limit}",
            node.tag_name().name()
        ),
    )
    .at(attr_at(source, node, attr))
    .label(format!("expected at most {limit}"))
    .help("MuJoCo would try to allocate it (and abort when it cannot); see docs/limits.md")
}

/// `<option>`: every number finite (a NaN gravity makes every reward NaN), and the timestep in
/// (0, `MAX_TIMESTEP`]; E0105 otherwise.
fn option_numbers(
    node: roxmltree::Node,
    source: &std::sync::Arc<SourceFile>,
    out: &mut Vec<Diagnostic>,
) {
    for a in node.attributes() {
        let nums: Vec<f64> = a
            .value()
            .split_whitespace()
            .map_while(|x| x.parse().ok())
            .collect();
        let bad = nums.iter().any(|x| !x.is_finite())
            || (a.name() == "timestep"
                && nums
                    .first()
                    .is_some_and(|&t| !(t > 0.0 && t <= MAX_TIMESTEP)));
        if bad {
            let expected = if a.name() == "timestep" {
                format!("a timestep in (0, {MAX_TIMESTEP}] seconds")
            } else {
                "finite numbers".to_string()
            };
            out.push(
                Diagnostic::new(
                    Code::E0105,
                    format!("<option {}=\"{}\"> is not {expected}", a.name(), a.value()),
                )
                .at(attr_at(source, node, a.name()))
                .label(format!("expected {expected}")),
            );
        }
    }
}

/// `<size>`: the per-element user sizes, `nkey`, the buffer sizes and `memory`.
fn stated_sizes(
    node: roxmltree::Node,
    source: &std::sync::Arc<SourceFile>,
    out: &mut Vec<Diagnostic>,
) {
    for a in node.attributes() {
        let name = a.name();
        let limit = if name.starts_with("nuser_") || name == "nkey" {
            MAX_PER_ELEMENT
        } else if matches!(name, "nuserdata" | "nconmax" | "njmax" | "nstack") {
            MAX_BUFFER_ENTRIES
        } else {
            continue;
        };
        if let Some(n) = int_attr(node, name)
            && n > limit
        {
            out.push(over(source, node, name, n.to_string(), limit.to_string()));
        }
    }
    if let Some(m) = node.attribute("memory")
        && let Some(bytes) = memory_bytes(m)
        && bytes > MAX_ARENA_BYTES as f64
    {
        out.push(over(
            source,
            node,
            "memory",
            m.trim().to_string(),
            human_bytes(MAX_ARENA_BYTES),
        ));
    }
}

/// `<texture>` and `<hfield>`: the samples of their grid.
fn grid_samples(
    node: roxmltree::Node,
    tag: &str,
    source: &std::sync::Arc<SourceFile>,
    out: &mut Vec<Diagnostic>,
) {
    let (a, b) = if tag == "texture" {
        ("width", "height")
    } else {
        ("nrow", "ncol")
    };
    let n = int_attr(node, a).unwrap_or(1).max(1) as i128
        * int_attr(node, b).unwrap_or(1).max(1) as i128;
    if n > MAX_GRID as i128 {
        out.push(over(
            source,
            node,
            a,
            format!("{n} samples ({a} × {b})"),
            MAX_GRID.to_string(),
        ));
    }
}

/// `<replicate>`, `<composite>`, `<flexcomp>`: the copies their `count` makes.
fn copy_count(
    node: roxmltree::Node,
    tag: &str,
    source: &std::sync::Arc<SourceFile>,
    out: &mut Vec<Diagnostic>,
) {
    let n: i128 = node
        .attribute("count")
        .map(|c| {
            c.split_whitespace()
                .filter_map(|x| x.parse::<f64>().ok())
                .map(|x| (x as i128).max(1))
                .product()
        })
        .unwrap_or(1);
    if n > MAX_GRID as i128 {
        out.push(over(
            source,
            node,
            "count",
            format!("{n} copies of <{tag}>"),
            MAX_GRID.to_string(),
        ));
    }
}

/// The first element nested deeper than `MAX_NESTING` (the document as a whole counts as level 0,
/// its root element as 1): E0110 at its start tag. Walks the tree without recursion.
pub fn check_xml_depth(
    doc: &roxmltree::Document,
    source: &std::sync::Arc<SourceFile>,
) -> Option<Diagnostic> {
    // Pre-order: a parent's depth is known before its children's.
    let mut depth: Vec<u32> = vec![0; doc.descendants().count()];
    for n in doc.descendants() {
        let d = match n.parent() {
            Some(p) => depth[p.id().get_usize()] + u32::from(n.is_element()),
            None => 0,
        };
        depth[n.id().get_usize()] = d;
        if d as usize > MAX_NESTING {
            let start = n.range().start;
            let tag = n.tag_name().name();
            return Some(
                Diagnostic::new(
                    Code::E0110,
                    format!(
                        "<{tag}> is nested {d} elements deep, beyond envc's limit of {MAX_NESTING}"
                    ),
                )
                .at(Location::new(source, start..start + 1 + tag.len()))
                .label(format!("expected at most {MAX_NESTING} nested elements"))
                .help(
                    "MuJoCo's reader stops near 1,000 levels and envc's readers recurse per \
                     level; see docs/limits.md",
                ),
            );
        }
    }
    None
}

/// E0302 at the `<include file>` that names a file already being read (`chain`: the including
/// files, outermost first, then the file named again).
pub fn include_cycle(chain: &[&Path], at: Option<Location>) -> Diagnostic {
    let names: Vec<String> = chain.iter().map(|p| p.display().to_string()).collect();
    Diagnostic::new(
        Code::E0302,
        format!("<include> cycle: {}", names.join(" includes ")),
    )
    .at_opt(at)
    .label("this file is already being read")
    .help("remove the <include> that closes the cycle")
}

/// E0110 at the `<include file>` nested deeper than `MAX_INCLUDE_DEPTH`.
pub fn include_too_deep(at: Option<Location>) -> Diagnostic {
    Diagnostic::new(
        Code::E0110,
        format!("<include> nested deeper than envc's limit of {MAX_INCLUDE_DEPTH}"),
    )
    .at_opt(at)
    .label(format!(
        "expected at most {MAX_INCLUDE_DEPTH} nested includes"
    ))
    .help("see docs/limits.md")
}

/// E0110 for the body beyond `MAX_BODIES` (`what` names it: `<body>`, a URDF link).
pub fn too_many_bodies(what: &str) -> Diagnostic {
    Diagnostic::new(
        Code::E0110,
        format!(
            "{what} is body number {}, beyond envc's limit of {MAX_BODIES} bodies in one model",
            MAX_BODIES + 1
        ),
    )
    .label(format!("expected at most {MAX_BODIES} bodies"))
    .help("MuJoCo's compile time grows with the square of the body count; see docs/limits.md")
}

/// MuJoCo's `memory` size: a number of bytes with an optional K/M/G/T/P/E suffix (powers of 1024).
fn memory_bytes(s: &str) -> Option<f64> {
    let s = s.trim();
    let (num, scale) = match s.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => {
            let p = "KMGTPE".find(c.to_ascii_uppercase())? as i32 + 1;
            (&s[..i], 1024f64.powi(p))
        }
        _ => (s, 1.0),
    };
    num.trim().parse::<f64>().ok().map(|n| n * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_sizes_read_like_mujoco() {
        assert_eq!(memory_bytes("100M"), Some(100.0 * 1024.0 * 1024.0));
        assert_eq!(memory_bytes("2G"), Some(2.0 * 1024f64.powi(3)));
        assert_eq!(memory_bytes("4096"), Some(4096.0));
        assert_eq!(memory_bytes("1Q"), None);
    }

    #[test]
    fn devices_and_directories_are_not_files() {
        assert!(matches!(
            read_text(Path::new("/dev/zero"), MAX_SPEC_BYTES),
            Err(ReadError::NotAFile("device"))
        ));
        assert!(matches!(
            read_text(Path::new("/"), MAX_SPEC_BYTES),
            Err(ReadError::NotAFile("directory"))
        ));
    }

    #[test]
    fn nesting_beyond_the_limit_is_located() {
        let deep = |n: usize| {
            format!(
                "<mujoco><worldbody>\n{}{}</worldbody></mujoco>",
                "<body><geom size=\".01\"/>".repeat(n),
                "</body>".repeat(n)
            )
        };
        // <mujoco> and <worldbody> are two levels and each body holds a geom one level deeper:
        // 497 bodies fit (the last geom at level 500), 498 do not.
        let ok = deep(MAX_NESTING - 3);
        let doc = roxmltree::Document::parse(&ok).unwrap();
        assert!(check_xml_depth(&doc, &SourceFile::new("m.xml", ok.clone())).is_none());
        let text = deep(10_000);
        let doc = roxmltree::Document::parse(&text).unwrap();
        let d = check_xml_depth(&doc, &SourceFile::new("m.xml", text.clone())).unwrap();
        assert_eq!(d.code, Code::E0110);
        assert!(
            d.message.starts_with("<geom> is nested 501"),
            "{}",
            d.message
        );
        // The geom of body 498: after 497 bodies of 24 characters and `<body>` on line 2.
        assert_eq!(d.position(), Some(format!("m.xml:2:{}", 497 * 24 + 6 + 1)));
    }

    #[test]
    fn stated_sizes_over_the_limits_are_located() {
        let text = "<mujoco>\n  <size nuser_geom=\"999999999\" memory=\"64G\"/>\n  <asset><texture name=\"t\" builtin=\"checker\" width=\"100000\" height=\"100000\"/></asset>\n</mujoco>\n";
        let file = SourceFile::new("m.xml", text.to_string());
        let doc = roxmltree::Document::parse(text).unwrap();
        let d = check_mjcf_sizes(&doc, &file);
        let msgs: Vec<_> = d.iter().map(|d| (d.code, d.position())).collect();
        assert_eq!(
            msgs,
            [
                (Code::E0110, Some("m.xml:2:21".to_string())),
                (Code::E0110, Some("m.xml:2:40".to_string())),
                (Code::E0110, Some("m.xml:3:53".to_string())),
            ]
        );
    }
}
