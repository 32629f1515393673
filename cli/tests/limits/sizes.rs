//! Work beyond a limit, refused before it starts: models nested too deep or with too many
//! bodies, terrain with too much to build.

use std::path::{Path, PathBuf};

use super::{Edits, ROOT, Scratch, envc, refused, s};

/// A minimal task spec over `model` (MJCF or URDF) in `dir`.
fn tiny_spec(dir: &Path, model: &str, text: &str) -> PathBuf {
    std::fs::write(dir.join(model), text).unwrap();
    let spec = dir.join(format!("{model}.toml"));
    std::fs::write(
        &spec,
        format!(
            "[env]\nid = \"Deep-v0\"\n\n[params]\nxml_file = {{ default = \"{model}\" }}\n\
             frame_skip = {{ default = 1 }}\nmax_episode_steps = {{ default = 10 }}\n\n\
             [observation.qpos]\nsource = \"qpos\"\n"
        ),
    )
    .unwrap();
    spec
}

#[test]
fn deeply_nested_models_are_refused_not_a_stack_overflow() {
    let dir = Scratch::new("nesting");
    let nested = |open: &str, close: &str, n: usize| open.repeat(n) + &close.repeat(n);
    let cases = [
        (
            "bodies.xml",
            format!(
                "<mujoco><worldbody>{}</worldbody></mujoco>",
                nested(r#"<body><geom size=".01"/>"#, "</body>", 10_000)
            ),
        ),
        (
            "defaults.xml",
            format!(
                "<mujoco><default>{}</default><worldbody><body><freejoint/><geom size=\".1\"/></body></worldbody></mujoco>",
                nested(r#"<default class="c">"#, "</default>", 50_000)
            ),
        ),
        (
            "frames.xml",
            format!(
                "<mujoco><worldbody><body><freejoint/><geom size=\".1\"/>{}</body></worldbody></mujoco>",
                nested("<frame>", "</frame>", 100_000)
            ),
        ),
    ];
    for (model, xml) in &cases {
        let spec = tiny_spec(&dir.0, model, xml);
        for args in [&["check", s(&spec)][..], &["check", "--compile", s(&spec)]] {
            let text = refused(&envc(args), "E0110");
            assert!(text.contains("nested 501 elements deep"), "{model}: {text}");
        }
    }
    // A URDF chain deeper than the limit (its XML is flat).
    let mut urdf = String::from("<robot name=\"chain\">\n");
    for i in 0..=600 {
        urdf += &format!("<link name=\"l{i}\"/>\n");
    }
    for i in 0..600 {
        urdf += &format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n",
            i + 1
        );
    }
    urdf += "</robot>\n";
    let spec = tiny_spec(&dir.0, "chain.urdf", &urdf);
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("link `l500` is 501 links deep"), "{text}");
}

#[test]
fn models_with_more_bodies_than_the_limit_are_refused_before_compiling() {
    let dir = Scratch::new("bodies");
    let flat: String = (0..50_000)
        .map(|i| format!("<body name=\"b{i}\"><geom size=\".01\"/></body>\n"))
        .collect();
    let spec = tiny_spec(
        &dir.0,
        "flat.xml",
        &format!("<mujoco><worldbody>\n{flat}</worldbody></mujoco>"),
    );
    let started = std::time::Instant::now();
    let text = refused(&envc(&["check", "--compile", s(&spec)]), "E0110");
    assert!(text.contains("body number 5001"), "{text}");
    // The 5001st body, on line 5002.
    assert!(text.contains("flat.xml:5002:1"), "{text}");
    assert!(started.elapsed().as_secs() < 20, "{:?}", started.elapsed());
    // 5,000 bodies still compile.
    let ok: String = (0..5_000)
        .map(|i| format!("<body name=\"b{i}\"><geom size=\".01\"/></body>\n"))
        .collect();
    let spec = tiny_spec(
        &dir.0,
        "ok.xml",
        &format!("<mujoco><worldbody>\n{ok}</worldbody></mujoco>"),
    );
    let o = envc(&["check", s(&spec)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A URDF of 20,000 links.
    let mut urdf = String::from("<robot name=\"many\">\n<link name=\"base\"/>\n");
    for i in 0..20_000 {
        urdf += &format!(
            "<link name=\"l{i}\"/><joint name=\"j{i}\" type=\"fixed\"><parent link=\"base\"/><child link=\"l{i}\"/></joint>\n"
        );
    }
    urdf += "</robot>\n";
    let spec = tiny_spec(&dir.0, "many.urdf", &urdf);
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("link `l4999`"), "{text}");
    // Bodies a spec adds count with the model's (Hopper has 5 with the world).
    let added: String = (0..5_000)
        .map(|i| format!("[bodies.added{i}]\npos = [0.0, 0.0, 1.0]\n"))
        .collect();
    let spec = dir.spec("hopper.toml", &[], &[]);
    let mut text = std::fs::read_to_string(&spec).unwrap();
    text.push('\n');
    text.push_str(&added);
    std::fs::write(&spec, text).unwrap();
    let text = refused(&envc(&["check", s(&spec)]), "E0110");
    assert!(text.contains("[bodies.added4995]"), "{text}");
}

/// The rough terrain example with `edits`, its model path made absolute, in `dir`.
fn rough_spec(dir: &Path, name: &str, edits: Edits) -> PathBuf {
    let mut text = std::fs::read_to_string(
        Path::new(ROOT).join("specs/examples/mjlab_velocity_rough_go1.toml"),
    )
    .unwrap()
    .replace("\"../../assets/", &format!("\"{ROOT}/assets/"));
    for (a, b) in edits {
        assert!(text.contains(a), "{a} not in the rough spec");
        text = text.replacen(a, b, 1);
    }
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn terrain_work_beyond_its_limits_is_refused_before_anything_is_built() {
    let dir = Scratch::new("terrain-work");
    let cases: [(&str, Edits); 5] = [
        // Billions of stairs boxes: an allocation of 6 GB aborted envc.
        ("stairs", &[("step_width = 0.3", "step_width = 1e-6")]),
        // Default stairs on 1000 m tiles: did not compile in 30 s.
        (
            "tiles",
            &[("tile_size = [8.0, 8.0]", "tile_size = [1000.0, 1000.0]")],
        ),
        // A 4 GiB table of height levels: abort.
        (
            "levels",
            &[(
                "noise = [0.02, 0.10]\nnoise_step = 0.02\n",
                "noise = [-1000.0, 1000.0]\nnoise_step = 1e-6\nvertical_scale = 1e-6\n",
            )],
        ),
        // Saturated integer heights: an index out of bounds.
        (
            "saturation",
            &[(
                "noise_step = 0.02\n",
                "noise_step = 0.02\nvertical_scale = 1e-300\n",
            )],
        ),
        // A slope too tall for its scale: reported at its key, not by MuJoCo at the model.
        ("slope", &[("slope = [0.0, 1.0]", "slope = [0.0, 1000.0]")]),
    ];
    for (name, edits) in cases {
        let edits: Vec<(&str, &str)> = if name == "slope" {
            vec![
                edits[0],
                (
                    "border_width = 0.25\n",
                    "border_width = 0.25\nvertical_scale = 1e-4\n",
                ),
            ]
        } else {
            edits.to_vec()
        };
        let spec = rough_spec(&dir.0, &format!("{name}.toml"), &edits);
        for args in [
            &["check", "--compile", s(&spec)][..],
            &["run", s(&spec), "--episodes", "1"],
        ] {
            let text = refused(&envc(args), "E0110");
            assert!(text.contains(&format!("{}.toml:", name)), "{name}: {text}");
        }
    }
}
