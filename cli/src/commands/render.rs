//! `envc render ID|SPEC [--policy zero|random|replay --actions A.npy] [--seed S] [--episodes N]
//! [--camera NAME] [--size WxH] [--set k=v ...] --out run.mp4|run.gif|frames/`: episodes rendered
//! headless (EGL) as Gymnasium's `RecordVideo` records them (a frame after every reset and every
//! step), for every kind of spec (a maze with its goal marker, a multi-agent spec's whole robot).
//!
//! Videos are encoded by Debian's `ffmpeg`, run as a subprocess that reads raw rgb24 frames on
//! stdin: it is what `RecordVideo` (through moviepy / imageio-ffmpeg) runs too, it is packaged and
//! maintained, and it writes H.264 MP4 and GIF (with a per-video palette) without adding a codec
//! to the build. PNG frames are written by the `png` crate, so they need no ffmpeg. The output is
//! written under a temporary name and renamed into place.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, anyhow, bail};
use envc::render::RenderMode;
use envc::rng::NumpyRng;
use envspec::{Code, Diagnostic};
use indicatif::{ProgressBar, ProgressStyle};

use crate::Outcome;
use envc::{JointAction, JointEnv};

#[derive(clap::Args)]
pub struct Args {
    /// Spec file or bundled env id (task, maze or multi-agent).
    spec: String,
    /// `run.mp4` (H.264), `run.gif`, or a new or empty directory (ending in `/`) for PNG frames.
    #[arg(long, value_name = "PATH")]
    out: PathBuf,
    #[arg(long, value_enum, default_value = "random")]
    policy: Policy,
    /// With `--policy replay`: a float32 or float64 `.npy` array [T, act_dim]; episodes take rows
    /// in order.
    #[arg(long, value_name = "A.npy")]
    actions: Option<PathBuf>,
    /// Seed of the first reset (later episodes continue the stream) and of the random policy.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Episodes to render (1 to 10,000: every frame is encoded).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    episodes: u64,
    /// A camera of the model, by name (the `camera_name` parameter).
    #[arg(long, value_name = "NAME")]
    camera: Option<String>,
    /// Frame size (the `width` and `height` parameters; default 480x480).
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Episode length cap (a continuing maze, a spec without `max_episode_steps`); at least 1.
    #[arg(long, default_value_t = 1000, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    max_steps: u64,
    /// Parameter overrides (`key=value`, TOML literal values).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// A multi-agent spec: draw each agent's limbs in its own colour (MaMuJoCo draws the model's).
    #[arg(long)]
    color_agents: bool,
}

#[derive(clap::ValueEnum, Clone, Copy, PartialEq)]
enum Policy {
    Zero,
    Random,
    Replay,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Output {
    Mp4,
    Gif,
    Frames,
}

fn e1506(message: String, help: &str) -> anyhow::Error {
    anyhow!("{}", Diagnostic::new(Code::E1506, message).help(help))
}

fn output_kind(out: &Path) -> Result<Output> {
    let s = out.to_string_lossy();
    if s.ends_with('/') || out.is_dir() {
        return Ok(Output::Frames);
    }
    match out.extension().and_then(|e| e.to_str()) {
        Some("mp4") => Ok(Output::Mp4),
        Some("gif") => Ok(Output::Gif),
        _ => Err(e1506(
            format!("cannot tell what to write to {}", out.display()),
            "expected a path ending in .mp4 or .gif, or a directory (ending in /) for PNG frames",
        )),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| anyhow!("--size {s}: expected WxH, e.g. 640x480"))?;
    let p = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| (1..=16384).contains(&n))
    };
    match (p(w), p(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => bail!("--size {s}: expected WxH with both from 1 to 16384"),
    }
}

/// Where frames go: ffmpeg's stdin (a video), or one PNG file per frame in a directory.
enum Sink {
    Ffmpeg(std::process::Child),
    Png { dir: PathBuf, next: u64 },
}

impl Sink {
    fn open(kind: Output, w: u32, h: u32, fps: u32, dest: &Path) -> Result<Sink> {
        match kind {
            Output::Frames => Ok(Sink::Png {
                dir: dest.to_path_buf(),
                next: 1,
            }),
            Output::Mp4 => encoder(false, w, h, fps, dest).map(Sink::Ffmpeg),
            Output::Gif => encoder(true, w, h, fps, dest).map(Sink::Ffmpeg),
        }
    }

    fn write(&mut self, rgb: &[u8], w: u32, h: u32) -> Result<()> {
        match self {
            Sink::Ffmpeg(c) => {
                let stdin = c.stdin.as_mut().expect("piped");
                stdin.write_all(rgb).map_err(|e| {
                    e1506(
                        format!("ffmpeg stopped reading frames: {e}"),
                        "see ffmpeg's message above",
                    )
                })
            }
            Sink::Png { dir, next } => {
                // Numbered from 1, as ffmpeg's image2 muxer numbers them.
                let path = dir.join(format!("frame_{next:06}.png"));
                write_png(&path, rgb, w, h).map_err(|e| {
                    e1506(
                        format!("cannot write {}: {e}", path.display()),
                        "check the path and the free space",
                    )
                })?;
                *next += 1;
                Ok(())
            }
        }
    }

    /// Waits for ffmpeg to finish the video; PNG frames are complete once written.
    fn finish(self) -> Result<()> {
        let Sink::Ffmpeg(mut c) = self else {
            return Ok(());
        };
        drop(c.stdin.take());
        let out = c.wait_with_output().context("waiting for ffmpeg")?;
        if !out.status.success() {
            return Err(e1506(
                format!(
                    "ffmpeg failed: {}",
                    String::from_utf8_lossy(&out.stderr).trim()
                ),
                "check the output path and that ffmpeg has libx264 (Debian's ffmpeg does)",
            ));
        }
        Ok(())
    }
}

/// One 8-bit RGB PNG, rows top first (as `render` returns them).
fn write_png(path: &Path, rgb: &[u8], w: u32, h: u32) -> Result<()> {
    let file = std::fs::File::create(path)?;
    let mut enc = png::Encoder::new(BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    // Frames of a run are many: fast deflate, still lossless.
    enc.set_compression(png::Compression::Fast);
    let mut writer = enc.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(())
}

/// ffmpeg reading raw rgb24 frames of `w`×`h` at `fps` on stdin, writing `dest` (H.264 MP4, or
/// a GIF).
fn encoder(gif: bool, w: u32, h: u32, fps: u32, dest: &Path) -> Result<std::process::Child> {
    let mut c = Command::new("ffmpeg");
    c.args([
        "-hide_banner",
        "-loglevel",
        "error",
        "-y",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
    ])
    .args(["-s", &format!("{w}x{h}"), "-r", &fps.to_string(), "-i", "-"]);
    if gif {
        c.args([
            "-vf",
            "split[a][b];[a]palettegen[p];[b][p]paletteuse",
            "-f",
            "gif",
        ]);
    } else {
        // yuv420p (what players expect) needs even sides: pad by one pixel when odd.
        c.args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-f",
            "mp4",
        ]);
    }
    c.arg(dest)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    c.spawn().map_err(|e| {
        e1506(
            format!("cannot run ffmpeg, which encodes .mp4 and .gif: {e}"),
            "install Debian's ffmpeg: `sudo apt-get install ffmpeg` (scripts/setup.sh installs it as root); PNG frames (`--out frames/`) need no ffmpeg",
        )
    })
}

pub fn run(args: Args) -> Result<Outcome> {
    let kind = output_kind(&args.out)?;
    check_destination(&args.out, kind)?;
    let mut env = open_env(&args)?;
    let space = env.action_space().clone();
    let act_dim = env.act_dim();
    let replay = replay_actions(&args, &env, act_dim)?;
    // Gymnasium's render_fps: np.round(1/dt), halves to even (the Kitchen's 12.5 is 12); the
    // maze classes declare 50.
    let fps = if env.kind() == envspec::Kind::Maze {
        50
    } else {
        (1.0 / env.dt()).round_ties_even().max(1.0) as u32
    };
    let limit = env
        .max_episode_steps()
        .unwrap_or(args.max_steps)
        .min(args.max_steps.max(1));

    let tmp = temporary_output(&args.out, kind)?;
    let episodes = Episodes {
        args: &args,
        kind,
        fps,
        limit,
        dest: &tmp,
        space: &space,
        replay: &replay,
    };
    let (frames, w, h) = match episodes.render(&mut env) {
        Ok(x) => x,
        Err(e) => {
            let _ = if kind == Output::Frames {
                std::fs::remove_dir_all(&tmp)
            } else {
                std::fs::remove_file(&tmp)
            };
            return Err(e);
        }
    };
    // An empty directory may stand where the frames go (checked empty before rendering).
    if kind == Output::Frames && args.out.is_dir() {
        let _ = std::fs::remove_dir(&args.out);
    }
    std::fs::rename(&tmp, &args.out).map_err(|e| {
        e1506(
            format!("cannot move the result to {}: {e}", args.out.display()),
            "check the path",
        )
    })?;
    println!(
        "{}: {frames} frames of {w}x{h} at {fps} fps -> {}",
        env.id(),
        args.out.display()
    );
    Ok(Outcome::Ok)
}

/// Refuses a `--out` the result must not be renamed over.
fn check_destination(out: &Path, kind: Output) -> Result<()> {
    // The result is renamed over `--out`: never over a device, FIFO or socket (the node itself
    // would be replaced, for every program on the machine).
    if let Ok(m) = std::fs::metadata(out)
        && !m.is_file()
        && !(m.is_dir() && kind == Output::Frames)
    {
        bail!(
            "error[E1410]: cannot write {}: it is not a regular file; envc writes an output whole and renames it into place",
            out.display()
        );
    }
    // Frames go into a directory of their own: never mixed with (or over) files already there.
    if kind == Output::Frames
        && out
            .read_dir()
            .is_ok_and(|mut entries| entries.next().is_some())
    {
        bail!(
            "error[E1412]: {} exists and is not empty; `envc render` writes PNG frames into a new or empty directory, never over files already there",
            out.display()
        );
    }
    Ok(())
}

/// The env to render, with `--camera` and `--size` as parameter overrides.
fn open_env(args: &Args) -> Result<envc::AnyEnv> {
    let mut sets = args.set.clone();
    if let Some(c) = &args.camera {
        sets.push(format!("camera_name={c:?}"));
    }
    if let Some(s) = &args.size {
        let (w, h) = parse_size(s)?;
        sets.push(format!("width={w}"));
        sets.push(format!("height={h}"));
    }
    let mut env = crate::target::env(&args.spec, &sets)?;
    if args.color_agents {
        match &mut env {
            envc::AnyEnv::MultiAgent(e) => e.color_agents(true),
            other => {
                return Err(crate::target::unsupported(
                    "render --color-agents",
                    other.id(),
                    other.kind(),
                    "colours the agents of a multi-agent spec",
                    "leave out --color-agents, or render a factorization (e.g. MaMuJoCo-Ant-v1)",
                ));
            }
        }
    }
    Ok(env)
}

/// The rows of `--actions`, flat, for `--policy replay` (empty for the other policies).
fn replay_actions(args: &Args, env: &envc::AnyEnv, act_dim: usize) -> Result<Vec<f64>> {
    Ok(match (args.policy, &args.actions) {
        (Policy::Replay, Some(p)) => {
            let a = envc::npy::read_matrix(p)?.into_f64();
            crate::target::action_file_shape(p, a.dim(), env.id(), act_dim)?;
            a.iter().copied().collect::<Vec<f64>>()
        }
        (Policy::Replay, None) => bail!("--policy replay needs --actions A.npy"),
        (_, Some(_)) => bail!("--actions is only used with --policy replay"),
        _ => vec![],
    })
}

/// Where the output is written before it is complete: a temporary name next to `--out`, renamed
/// when complete (a directory, made here, for PNG frames).
fn temporary_output(out: &Path, kind: Output) -> Result<PathBuf> {
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frames".into());
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let tmp = parent.join(format!(".{name}.partial-{}", std::process::id()));
    if kind == Output::Frames {
        std::fs::create_dir_all(&tmp).map_err(|e| {
            e1506(
                format!("cannot create {}: {e}", tmp.display()),
                "check the path",
            )
        })?;
    }
    Ok(tmp)
}

/// The episodes to render and where their frames go.
struct Episodes<'a> {
    args: &'a Args,
    kind: Output,
    fps: u32,
    /// Steps per episode at most.
    limit: u64,
    dest: &'a Path,
    space: &'a envc::BoxSpace,
    /// `--actions`, flat (`--policy replay`).
    replay: &'a [f64],
}

impl Episodes<'_> {
    /// Every episode's frames written to the sink (opened at the first frame, whose size it
    /// takes); the frame count and size.
    fn render(&self, env: &mut envc::AnyEnv) -> Result<(u64, u32, u32)> {
        let args = self.args;
        let (limit, act_dim) = (self.limit, env.act_dim());
        let mut policy_rng = NumpyRng::from_seed(args.seed);
        let mut action = vec![0.0; act_dim];
        let mut row = 0usize;
        let bar = ProgressBar::new(args.episodes * limit);
        bar.set_style(
            ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} steps ({elapsed}, eta {eta})",
            )
            .expect("static template")
            .progress_chars("=> "),
        );
        bar.set_message(format!("rendering {}", env.id()));
        let mut child: Option<(Sink, u32, u32)> = None;
        let mut frames = 0u64;
        let mut write =
            |env: &mut envc::AnyEnv, child: &mut Option<(Sink, u32, u32)>| -> Result<()> {
                let f = env.render(RenderMode::RgbArray)?;
                let (w, h) = (f.width as u32, f.height as u32);
                if child.is_none() {
                    *child = Some((Sink::open(self.kind, w, h, self.fps, self.dest)?, w, h));
                }
                let (sink, ..) = child.as_mut().expect("just set");
                sink.write(f.rgb.unwrap_or(&[]), w, h)?;
                frames += 1;
                Ok(())
            };
        for ep in 0..args.episodes {
            env.try_reset(if ep == 0 { Some(args.seed) } else { None })?;
            write(env, &mut child)?;
            for t in 0..limit {
                match args.policy {
                    Policy::Random => {
                        for (i, a) in action.iter_mut().enumerate() {
                            *a = policy_rng.uniform(self.space.low[i], self.space.high[i]);
                        }
                    }
                    Policy::Replay => {
                        let n = self.replay.len() / act_dim;
                        if row >= n {
                            break;
                        }
                        action.copy_from_slice(&self.replay[row * act_dim..(row + 1) * act_dim]);
                        row += 1;
                    }
                    Policy::Zero => {}
                }
                let s = env.step_joint(JointAction::F64(&action))?;
                let done = s.terminated || s.truncated;
                write(env, &mut child)?;
                bar.inc(1);
                if done {
                    bar.inc(limit - t - 1);
                    break;
                }
            }
        }
        bar.finish_and_clear();
        let (sink, w, h) = child.ok_or_else(|| anyhow!("no frame was rendered"))?;
        sink.finish()?;
        Ok((frames, w, h))
    }
}
