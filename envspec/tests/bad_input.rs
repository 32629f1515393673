//! Bad input: every mistake gets a stable code, the exact line:col of the offending text, a
//! near-miss suggestion where one exists, and all mistakes of a spec are reported together.
//! Nothing here may panic inside the library: every call goes through `Result`.
//!
//! Most cases break a small hopper spec (`MINI`, in `bad_input/runner.rs`) whose line numbers are
//! stable; a few copy a real spec from `specs/gymnasium/`. Error codes are documented in
//! `docs/errors.md`.
//!
//! The cases are rows of `cases!` tables, each row its own `#[test]` so a failure names it. A row
//! lists the fields of a `Case` (`bad_input/runner.rs`): the edits to the spec, the overrides, and
//! the diagnostics that must come out, each with its code and whichever of its position, message,
//! help and label the row gives; `run` loads the spec and asserts them all. A row of several
//! `{ .. }` loads each in turn. Tests of other shapes (rendering, `Override::parse`, MJCF
//! includes) are plain functions next to the tables.

mod runner;

use std::path::Path;

use envspec::Code::*;
use envspec::{Code, Diagnostics, Override, Spec, load};
use runner::*;

/// The diagnostics of a spec text that must not parse.
fn parse_errors(path: &str, text: String) -> Diagnostics {
    match Spec::parse(Path::new(path), text) {
        Ok(_) => panic!("`{path}` parsed"),
        Err(d) => d,
    }
}

// ---------------------------------------------------------------------------------------------
// The base spec is fine.

cases! {
    the_base_spec_resolves {
        expect: Resolves(|spec| {
            assert_eq!(spec.obs_dim, 5 + 6);
            assert_eq!(spec.reward.len(), 3);
        }),
    }
}

// ---------------------------------------------------------------------------------------------
// Unknown keys, names and kinds: near-miss suggestions.

cases! {
    unknown_key_suggests_the_near_miss {
        edits: &[("weight = \"healthy_reward\"", "wieght = \"healthy_reward\"")],
        expect: Fails(&[err(E0101).pos("SCRATCH/spec.toml:29:1")
            .msg("unknown key `wieght` in [reward.healthy]")
            .help("did you mean `weight`?")
            .label("expected one of: kind, weight, cost, info, when, at, only_if, unless, doc, paid_when_unhealthy")]),
    }

    unknown_top_level_and_section_keys_suggest_the_near_miss {
        edits: &[("clip = [", "clp = [")],
        append: "\n[rewards.extra]\nkind = \"constant\"\n",
        // Top-level keys are checked first.
        expect: Fails(&[
            err(E0101).at("53:2").msg("unknown key `rewards` in the spec (top level)")
                .help("did you mean `reward`?"),
            err(E0101).at("18:1").msg("unknown key `clp` in [observation.qvel]")
                .help("did you mean `clip`?"),
        ]),
    }

    // [params] declares names, so a misspelt declaration is not an unknown key: it is found at the
    // reference to the intended name, and the suggestion names the misspelling.
    misspelt_parameter_declaration_is_caught_where_it_is_used {
        edits: &[("healthy_reward = 1.0", "helthy_reward = 1.0")],
        expect: Fails(&[err(E0201).at("29:10")
            .msg("`healthy_reward` is not a parameter of this spec")
            .help("did you mean `helthy_reward`?")]),
    }

    unknown_override_suggests_the_parameter {
        overrides: &["helthy_reward=2.0"],
        // Overrides have no spec location.
        expect: Fails(&[err(E0202).nowhere().msg("unknown parameter `helthy_reward` for Mini-v0")
            .help("did you mean `healthy_reward`?")
            .label("expected one of: xml_file, frame_skip, max_episode_steps, ctrl_cost_weight, healthy_reward, healthy_z_range, terminate_when_unhealthy")]),
    }

    unknown_reward_kind_suggests_the_near_miss {
        edits: &[("kind = \"sum_squares\"", "kind = \"sum_square\"")],
        expect: Fails(&[err(E0104).at("32:8")
            .msg("unknown reward kind `sum_square` in [reward.ctrl]")
            .help("did you mean `sum_squares`?")
            .label("expected one of: velocity, healthy, sum_squares, norm, quadratic, value, constant, weighted_square, goal_sparse, goal_dense, goal_missed, goal_distance, goals_missed, parts_reached, tracking, sum_abs, action_rate, feet_air_time, feet_slip, joint_limits, posture, feet_clearance, feet_swing_height, soft_landing, self_collisions")]),
    }

    unknown_health_reset_and_info_kinds {
        edits: &[
            ("kind = \"in_range\"", "kind = \"inrange\""),
            ("kind = \"uniform\"", "kind = \"uniformly\""),
        ],
        append: "\n[info.speed]\nkind = \"velocty\"\nsource = \"qpos[0]\"\n",
        expect: Fails(&[
            err(E0104).at("41:8").help("did you mean `in_range`?"),
            err(E0104).at("47:8").help("did you mean `uniform`?"),
            err(E0104).at("54:8").help("did you mean `velocity`?"),
        ]),
    }
}

// ---------------------------------------------------------------------------------------------
// Types of values and of overrides.

cases! {
    wrong_type_of_a_parameter_default {
        edits: &[("frame_skip = 4", "frame_skip = \"five\"")],
        expect: Fails(&[err(E0102).pos("SCRATCH/spec.toml:6:14")
            .msg("default of parameter `frame_skip` is not an integer")
            .label("expected an integer (type int)")]),
    } {
        // Long form; columns count characters, not bytes.
        edits: &[("frame_skip = 4", "frame_skip = { doc = \"Schritte über\", default = \"five\" }")],
        expect: Fails(&[err(E0102).at("6:49")]),
    }

    // `id` is checked without the model; the others when resolving. Syntax errors stop first.
    wrong_type_of_a_value_in_a_section {
        stage: Read,
        edits: &[
            ("id = \"Mini-v0\"", "id = 5"),
            ("source = \"qvel\"", "source = 3"),
            ("weight = \"ctrl_cost_weight\"", "weight = true"),
        ],
        expect: Fails(&[err(E0102).at("2:6").msg("env.id must be a string, found integer")]),
    } {
        edits: &[
            ("source = \"qvel\"", "source = 3"),
            ("weight = \"ctrl_cost_weight\"", "weight = true"),
        ],
        expect: Fails(&[
            err(E0102).at("17:10")
                .msg("source must be a selector string such as \"qpos[2:]\", found integer"),
            err(E0102).at("34:10")
                .msg("weight must be a number or a parameter name, found boolean"),
        ]),
    }

    override_of_the_wrong_type {
        overrides: &["healthy_z_range=abc"],
        // The override's own text is the "file" the error points into.
        expect: Fails(&[err(E0203).pos("<override healthy_z_range>:1:1")
            .msg("override of `healthy_z_range` is not a range [low, high] (type range)")
            .label("expected a range [low, high]; the default is [0.7, inf]")]),
    }

    all_bad_overrides_are_reported_together {
        overrides: &[
            "terminate_when_unhealthy=True",
            "frame_skip=5.0",
            "ctrl_cost_wieght=0.1",
            "healthy_z_range=[1.0]",
        ],
        expect: Fails(&[
            err(E0203).label("expected true or false; the default is true"),
            err(E0203).label("expected an integer; the default is 4"),
            err(E0202).help("did you mean `ctrl_cost_weight`?"),
            err(E0203).pos("<override healthy_z_range>:1:1"),
        ]),
    }

    good_overrides_use_toml_literals {
        overrides: &[
            "healthy_z_range=[0.3, inf]",
            "ctrl_cost_weight=1", // an integer is a fine float
            "terminate_when_unhealthy=false",
            "frame_skip=5",
        ],
        expect: Resolves(|spec| {
            assert_eq!(spec.frame_skip, 5);
            assert!(!spec.terminate_when_unhealthy);
        }),
    }

    invalid_parameter_values {
        edits: &[("healthy_z_range = [0.7, inf]", "healthy_z_range = [2.0, 1.0]")],
        overrides: &["frame_skip=0"],
        expect: Fails(&[
            // The bad value came from an override.
            err(E0105).nowhere().msg("frame_skip must be a positive integer"),
            // Reported where the range is used.
            err(E0105).at("43:9").msg("range: low 2 is above high 1"),
        ]),
    }
}

#[test]
fn override_text_without_equals_sign() {
    let d = match Override::parse("ctrl_cost_weight") {
        Ok(o) => panic!("parsed {o:?}"),
        Err(d) => d,
    };
    assert_eq!(d.code, Code::E0202);
    assert_eq!(
        d.message,
        "override `ctrl_cost_weight` is not of the form name=value"
    );
    assert!(Override::parse("=1").is_err());
}

// ---------------------------------------------------------------------------------------------
// Parameter references.

cases! {
    reference_to_an_undeclared_parameter {
        edits: &[
            ("weight = \"ctrl_cost_weight\"", "weight = \"ctrl_cost_wieght\""),
            (
                "terminate = \"terminate_when_unhealthy\"",
                "terminate = \"!terminate_when_unhealty\"",
            ),
            ("range = \"healthy_z_range\"", "range = \"healthy_range\""),
        ],
        expect: Fails(&[
            err(E0201).at("34:10").msg("`ctrl_cost_wieght` is not a parameter of this spec")
                .label("expected a number or the name of a parameter in [params]")
                .help("did you mean `ctrl_cost_weight`?"),
            // `!name` negates a bool parameter; the name after `!` is what is looked up.
            err(E0201).at("38:13").msg("`terminate_when_unhealty` is not a parameter of this spec")
                .help("did you mean `terminate_when_unhealthy`?"),
            err(E0201).at("43:9").help("did you mean `healthy_z_range`?"),
        ]),
    }

    reference_to_a_parameter_of_the_wrong_type {
        edits: &[
            ("terminate = \"terminate_when_unhealthy\"", "terminate = \"!healthy_reward\""),
            ("range = \"healthy_z_range\"", "range = \"ctrl_cost_weight\""),
        ],
        expect: Fails(&[
            err(E0102).msg("parameter `healthy_reward` is 1.0, not a bool"),
            err(E0102).msg("parameter `ctrl_cost_weight` is 0.001, not a range [low, high]"),
        ]),
    }

    dollar_parameter_in_a_selector {
        base: Real("ant.toml"),
        file: "ant.toml",
        edits: &[(
            "source = \"xpos[$main_body][0]\"\nweight",
            "source = \"xpos[$main_bdy][0]\"\nweight",
        )],
        expect: Fails(&[err(E0201).at_text("\"xpos[$main_bdy][0]\"")
            .label("expected an index or the name of a parameter in [params]")
            .help("did you mean `main_body`?")]),
    }
}

// ---------------------------------------------------------------------------------------------
// Selectors and model names.

cases! {
    body_name_not_in_the_model {
        edits: &[(FORWARD, "source = \"xpos[torsoo][0]\"\n\n[reward.healthy]")],
        expect: Fails(&[err(E0303).at("25:10")
            .msg("the model ASSETS/hopper.xml has no body named `torsoo`")
            .label("expected the name of a body of the model (5 named)")
            .help("did you mean `torso`?")]),
    }

    // Ant: `main_body` is used by the forward reward and two info entries.
    body_name_from_an_override_is_checked_at_every_use {
        base: Real("ant.toml"),
        file: "ant.toml",
        overrides: &["main_body=torsoo"],
        expect: Fails(&[
            err(E0303).at_text("\"xpos[$main_body][0]\"").help("did you mean `torso`?"),
            err(E0303).help("did you mean `torso`?"),
            err(E0303).help("did you mean `torso`?"),
        ]),
    }

    // Not an error: a joint name selects the joint's qpos (or dof) rows. A typo is E0303.
    joint_name_selects_its_entries {
        edits: &[(HEIGHT, "source = \"qpos[rootz]\"")],
        expect: Resolves(|spec| assert_eq!(spec.health[0].sources[0].indices, [1])),
    } {
        edits: &[(HEIGHT, "source = \"qpos[root_z]\"")],
        expect: Fails(&[err(E0303).help("did you mean `rootz`?")]),
    }

    bad_selector_syntax {
        edits: &[(HEIGHT, "source = \"qpos[1\"")],
        expect: Fails(&[err(E0401).at("42:10").msg("cannot read selector: missing `]`")]),
    } {
        edits: &[(HEIGHT, "source = \"qpos[]\"")],
        expect: Fails(&[err(E0401).at("42:10").msg("cannot read selector: empty `[]`")]),
    } {
        edits: &[(HEIGHT, "source = \"qpos[1,]\"")],
        expect: Fails(&[err(E0401).at("42:10")
            .msg("cannot read selector: an empty entry in a `,` list")]),
    } {
        edits: &[(HEIGHT, "source = \"qpos[1][0]\"")],
        expect: Fails(&[err(E0401).at("42:10")
            .msg("cannot read selector: `qpos` is a vector: one index only")]),
    } {
        edits: &[(HEIGHT, "source = \"xpos[torso][0][1]\"")],
        expect: Fails(&[err(E0401).at("42:10")
            .msg("cannot read selector: at most two indices (rows, then columns)")]),
    } {
        edits: &[(HEIGHT, "source = \"xpos[torso][w]\"")],
        expect: Fails(&[err(E0401).at("42:10").msg("`w` is not a column of `xpos`")]),
    } {
        edits: &[(HEIGHT, "source = \"xpos[torso].x.y\"")],
        expect: Fails(&[err(E0401).at("42:10")
            .msg("cannot read selector: `.x.y` is not a column name")]),
    }

    index_out_of_range {
        edits: &[(HEIGHT, "source = \"qpos[7]\"")],
        expect: Fails(&[err(E0304).at("42:10").msg("index 7 is out of range for 6 entries")
            .label("expected an index in -6..6")]),
    } {
        edits: &[(HEIGHT, "source = \"qpos[-7]\"")],
        expect: Fails(&[err(E0304).at("42:10").msg("index -7 is out of range for 6 entries")
            .label("expected an index in -6..6")]),
    } {
        edits: &[(HEIGHT, "source = \"qpos[0,6]\"")],
        expect: Fails(&[err(E0304).at("42:10").msg("index 6 is out of range for 6 entries")
            .label("expected an index in -6..6")]),
    } {
        edits: &[(HEIGHT, "source = \"xpos[torso][3]\"")],
        expect: Fails(&[err(E0304).at("42:10").msg("index 3 is out of range for 3 entries")
            .label("expected an index in -3..3")]),
    } {
        // Slices clamp like Python's and are never out of range.
        edits: &[(HEIGHT, "source = \"qpos[5:99]\"")],
        expect: Resolves(|spec| assert_eq!(spec.health[0].sources[0].indices, [5])),
    }

    unknown_selector_field {
        edits: &[("source = \"qvel\"", "source = \"qvell\"")],
        expect: Fails(&[err(E0402).at("17:10").msg("unknown field `qvell` in selector `qvell`")
            .help("did you mean `qvel`?")]),
    }

    sizes_that_do_not_fit {
        edits: &[(FORWARD, "source = \"qpos[0:2]\"\n\n[reward.healthy]")],
        append: "minus = \"qpos0[0:2]\"\n",
        expect: Fails(&[
            err(E0403).at("25:10").msg("a velocity needs one number, `qpos[0:2]` selects 2"),
            err(E0403).at("52:9").msg("`qpos[0]` has 1 elements but `qpos0[0:2]` has 2"),
        ]),
    } {
        // An array of the wrong length says how long it is.
        append: "\n[sites.tip]\nbody = \"torso\"\npos = [0.0, 0.1]\n",
        expect: Fails(&[err(E0102).msg_ends("found an array of 2 values")]),
    }
}

// ---------------------------------------------------------------------------------------------
// The model file.

cases! {
    missing_model_file {
        // A relative xml_file resolves against the spec's directory.
        edits: &[(XML_FILE, "'no_such_model.xml'")],
        expect: Fails(&[err(E0301).at("5:12")
            .msg_starts("cannot read model file SCRATCH/no_such_model.xml: ")
            .help("xml_file resolved to SCRATCH/no_such_model.xml")]),
    }

    missing_model_file_from_an_override {
        overrides: &["xml_file=/nonexistent/model.xml"],
        expect: Fails(&[err(E0301).nowhere().help("xml_file resolved to /nonexistent/model.xml")]),
    }

    malformed_model_file {
        files: &[(
            "broken.xml",
            "<mujoco>\n  <worldbody>\n    <body name='a'>\n  </worldbody>\n</mujoco>\n",
        )],
        edits: &[(XML_FILE, "'broken.xml'")],
        // At the XML error, in the model file, not at the spec's `xml_file`.
        expect: Fails(&[err(E0302).pos("SCRATCH/broken.xml:4:3")
            .msg("SCRATCH/broken.xml: not well-formed XML: expected 'body' tag, not 'worldbody' at 4:3")
            .label("expected well-formed MJCF")]),
    } {
        // Well-formed XML that is neither MJCF nor URDF (URDF is read: tests/urdf.rs).
        files: &[("robot.sdf", "<sdf version='1.6'/>\n")],
        edits: &[(XML_FILE, "'robot.sdf'")],
        expect: Fails(&[err(E0302).msg_ends("root element is <sdf>, not <mujoco>")]),
    }
}

// ---------------------------------------------------------------------------------------------
// The spec file itself.

cases! {
    invalid_toml {
        stage: Parse,
        file: "mini.toml",
        edits: &[("id = \"Mini-v0\"", "id = \"Mini-v0")],
        expect: Fails(&[err(E0100).pos("mini.toml:2:14")
            .msg("invalid TOML: invalid basic string, expected `\"`")]),
    }

    /// One missing `]` is one error, at the `[` it leaves open (the parser's recovery reads the
    /// next lines as more of the array and would report each of them).
    an_unclosed_array_is_one_error_at_its_bracket {
        stage: Parse,
        edits: &[("clip = [-10.0, 10.0]", "clip = [-10.0, 10.0")],
        expect: Fails(&[err(E0100).at("18:8")
            .label("this `[` is not closed (the next line was read as more of the array)")]),
    }

    unreadable_spec_file {
        base: Absent,
        file: "absent.toml",
        expect: Fails(&[err(E0600).nowhere()]),
    }

    missing_env_id {
        edits: &[("id = \"Mini-v0\"\n", "")],
        expect: Fails(&[err(E0103).pos("SCRATCH/spec.toml:1:2").msg("missing `id` in [env]")
            .label("expected `id = \"Name-v0\"`")]),
    }

    missing_env_table_and_required_parameters {
        base: Empty,
        stage: Parse,
        file: "empty.toml",
        expect: Fails(&[
            err(E0103).pos("empty.toml:1:1").msg("missing `[env]` table"),
            err(E0103).pos("empty.toml:1:1").msg("missing parameter `xml_file` in [params]"),
            err(E0103).pos("empty.toml:1:1").msg("missing parameter `frame_skip` in [params]"),
            err(E0103).pos("empty.toml:1:1")
                .msg("missing parameter `max_episode_steps` in [params]"),
        ]),
    }

    // `[agents]` is a factorization (envspec::multi_agent); the single-agent spec ignores it.
    agents_section_is_left_to_the_multi_agent_layer {
        stage: Parse,
        append: "\n[agents]\nsplit = 2\n",
        expect: Parses,
    }
}

#[test]
fn invalid_toml_reports_only_syntax_errors() {
    // The TOML parser recovers and may report several errors for one mistake; all are E0100.
    let text = with(
        &mini(),
        "frame_skip = 4",
        "frame_skip = { default = 4 doc = \"x\" }",
    );
    let d = parse_errors("mini.toml", text);
    assert!(!d.is_empty());
    assert!(d.iter().all(|e| e.code == Code::E0100), "{d}");
    assert_eq!(lc(&d.0[0]), "6:32");
    assert_eq!(
        d.0[0].message,
        "invalid TOML: extra assignment between key-value pairs, expected `,`"
    );
}

// ---------------------------------------------------------------------------------------------
// The reward sum.

cases! {
    sum_names_an_unknown_term {
        edits: &[(SUM, "sum = [[\"forward\", \"helthy\"], \"ctrl\"]")],
        // The unknown name, and the term it was meant to be, which is then missing.
        expect: Fails(&[
            err(E0501).at("21:20").msg("`helthy` in `sum` is not a reward term")
                .help("did you mean `healthy`?"),
            err(E0501).at("21:7").msg("reward term `healthy` is missing from `sum`"),
        ]),
    }

    sum_leaves_a_term_out_or_uses_it_twice {
        edits: &[(SUM, "sum = [\"forward\", \"ctrl\"]")],
        expect: Fails(&[err(E0501).at("21:7").msg("reward term `healthy` is missing from `sum`")
            .label("expected every term exactly once")]),
    } {
        edits: &[(SUM, "sum = [\"forward\", \"healthy\", \"ctrl\", \"ctrl\"]")],
        expect: Fails(&[err(E0501).msg("reward term `ctrl` is used 2 times in `sum`")]),
    }
}

// ---------------------------------------------------------------------------------------------
// All errors at once (and `run` checks that the last line counts them).

cases! {
    // Resolution: an unknown field, an undeclared parameter, an index out of range.
    three_independent_mistakes_give_three_diagnostics {
        edits: &[
            ("source = \"qvel\"", "source = \"qvell\""),
            ("weight = \"ctrl_cost_weight\"", "weight = \"ctrl_cost_wieght\""),
            (HEIGHT, "source = \"qpos[7]\""),
        ],
        expect: Fails(&[err(E0402).at("17:10"), err(E0201).at("34:10"), err(E0304).at("42:10")]),
    }

    // Checked without the model: a missing id, an unknown key, an unknown kind.
    three_independent_syntax_mistakes_give_three_diagnostics {
        stage: Parse,
        edits: &[
            ("id = \"Mini-v0\"\n", ""),
            ("weight = \"healthy_reward\"", "wieght = \"healthy_reward\""),
            ("kind = \"sum_squares\"", "kind = \"sum_square\""),
        ],
        expect: Fails(&[err(E0103).at("1:2"), err(E0101).at("28:1"), err(E0104).at("31:8")]),
    }

    three_mistakes_in_a_real_spec {
        base: Real("hopper.toml"),
        file: "hopper.toml",
        edits: &[
            ("source = \"qpos[2]\"", "source = \"qpos[7]\""),
            ("[observation.qvel]\nsource = \"qvel\"", "[observation.qvel]\nsource = \"qvell\""),
            ("weight = \"ctrl_cost_weight\"", "weight = \"ctrl_cost_wieght\""),
        ],
        expect: Fails(&[
            err(E0402).at_text("\"qvell\""),
            err(E0201).at_text("\"ctrl_cost_wieght\""),
            err(E0304).at_text("\"qpos[7]\""),
        ]),
    }
}

// ---------------------------------------------------------------------------------------------
// Rendering.

#[test]
fn rendered_diagnostic_is_pinned() {
    let text = with(&mini(), "kind = \"sum_squares\"", "kind = \"sum_square\"");
    let d = parse_errors("specs/mini.toml", text);
    let expected = "\
error[E0104]: unknown reward kind `sum_square` in [reward.ctrl]
  --> specs/mini.toml:32:8
   |
32 | kind = \"sum_square\"
   |        ^^^^^^^^^^^^ expected one of: velocity, healthy, sum_squares, norm, quadratic, value, constant, weighted_square, goal_sparse, goal_dense, goal_missed, goal_distance, goals_missed, parts_reached, tracking, sum_abs, action_rate, feet_air_time, feet_slip, joint_limits, posture, feet_clearance, feet_swing_height, soft_landing, self_collisions
   = help: did you mean `sum_squares`?
";
    assert_eq!(d.0[0].to_string(), expected);
    assert_eq!(d.to_string(), format!("{expected}\n1 error found"));
}

#[test]
fn rendered_text_names_the_file_line_and_column() {
    let s = Scratch::new("render");
    let text = with(&mini(), "source = \"qvel\"", "source = \"qvell\"");
    let p = s.write("spec.toml", &text);
    let Err(d) = load(&p, &[]) else {
        panic!("`{}` loaded", p.display())
    };
    let out = d.0[0].to_string();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "error[E0402]: unknown field `qvell` in selector `qvell`"
    );
    assert_eq!(lines[1], format!("  --> {}:17:10", p.display()));
    assert_eq!(lines[3], "17 | source = \"qvell\"");
    assert!(
        lines[4].starts_with("   |          ^^^^^^^ expected one of: qpos, qvel,"),
        "{out}"
    );
    assert_eq!(
        lines[5], "   = help: did you mean `qvel`?",
        "help is aligned with the gutter"
    );
}

#[test]
fn crlf_line_endings_give_the_same_positions() {
    let text =
        with(&mini(), "kind = \"sum_squares\"", "kind = \"sum_square\"").replace('\n', "\r\n");
    let d = parse_errors("crlf.toml", text);
    assert_eq!(lc(&d.0[0]), "32:8");
    assert!(
        d.0[0]
            .to_string()
            .contains("\n32 | kind = \"sum_square\"\n"),
        "no carriage return in the quoted line"
    );
}

// ---------------------------------------------------------------------------------------------
// Known problems (see the report that came with this file); un-ignore once fixed.

cases! {
    xml_file_with_a_non_path_type_is_an_error_not_a_panic {
        edits: &[(
            "xml_file = 'ASSETS/hopper.xml'",
            "xml_file = { default = 3, type = \"int\" }",
        )],
        expect: Fails(&[err(E0102).at("5:24")
            .msg("default of parameter `xml_file` is not a file path")]),
    }

    a_disabled_observation_segment_is_still_checked {
        edits: &[("source = \"qvel\"", "source = \"qvell\"\nwhen = false")],
        expect: Fails(&[err(E0402)]),
    }

    sum_is_checked_even_when_another_term_fails {
        edits: &[
            (SUM, "sum = [[\"forward\", \"healthy\"]]"),
            (FORWARD, "source = \"qpos[9]\"\n\n[reward.healthy]"),
        ],
        // The bad index, and `ctrl` (which resolved) missing from `sum`.
        expect: Fails(&[err(E0304), err(E0501)]),
    }

    empty_uniform_reset_bounds {
        edits: &[("scale = 5e-3", "scale = -5e-3")],
        expect: Fails(&[err(E0105).at("48:9")
            .msg("[reset.qpos]: uniform bounds [0.005, -0.005) are empty or infinite")]),
    }

    /// The codes split from E0104 (docs/errors.md): each means one thing, and each is located.
    out_of_range_duplicate_wrong_kind_and_maze_codes {
        // A reversed clip range: a number out of range.
        edits: &[("clip = [-10.0, 10.0]", "clip = [10.0, -10.0]")],
        expect: Fails(&[err(E0105).at("18:8")]),
    } {
        // `x_position` twice: once by its table name, once by `key`.
        append: "\n[info.x]\nkey = \"x_position\"\nsource = \"qpos[0]\"\n",
        expect: Fails(&[err(E0106).at("54:7")]),
    } {
        // A reset of something that is not qpos or qvel.
        edits: &[("target = \"qpos\"", "target = \"xpos[torso]\"")],
        expect: Fails(&[err(E0107).at("46:10")]),
    } {
        // `[maze]` in a task spec: found without the model.
        stage: Parse,
        append: "\n[maze]\nid = \"M-v0\"\n",
        expect: Fails(&[err(E0108).at("53:2")]),
    }

    /// `fails_if` without `op` is a missing key (E0103); an unknown `op` is E0104.
    fails_if_op_missing_or_unknown {
        edits: &[(HEALTH_CHECK, "kind = \"fails_if\"\nsource = \"qpos[1]\"\nvalue = 0.7")],
        expect: Fails(&[err(E0103).at("40:9")]),
    } {
        edits: &[(
            HEALTH_CHECK,
            "kind = \"fails_if\"\nsource = \"qpos[1]\"\nop = \"=<\"\nvalue = 0.7",
        )],
        expect: Fails(&[err(E0104).at("43:6")]),
    } {
        edits: &[(HEALTH_CHECK, "kind = \"fails_if\"\nsource = \"qpos[1]\"\nop = 1\nvalue = 0.7")],
        expect: Fails(&[err(E0102).at("43:6")]),
    }
}

/// An MJCF that includes itself, directly or through another file, is one located error (E0302
/// at the `<include file>` that closes the cycle), not a walk until a depth bound; includes
/// nested beyond `limits::MAX_INCLUDE_DEPTH` are E0110 at the deepest `<include>`. The reader
/// records every file it read, the including ones first.
#[test]
fn include_cycles_and_depth_are_one_located_error() {
    use envspec::ModelInfo;
    use envspec::source::Reader;
    let s = Scratch::new("include_cycle");
    let own = "<mujoco>\n  <include file=\"self.xml\"/>\n</mujoco>\n";
    let self_xml = s.write("self.xml", own);
    let d = ModelInfo::from_mjcf(&self_xml).expect_err("a self-include");
    assert_eq!(d.code, Code::E0302, "{d}");
    assert_eq!(lc(&d), find_lc(own, "self.xml\""), "{d}");
    assert!(d.message.contains("<include> cycle"), "{d}");

    let a_text = "<mujoco>\n  <include file=\"b.xml\"/>\n</mujoco>\n";
    let b_text = "<mujoco>\n\n  <include file=\"./a.xml\"/>\n</mujoco>\n";
    let a = s.write("a.xml", a_text);
    let b = s.write("b.xml", b_text);
    let mut reader = Reader::disk();
    let d = reader
        .run(|| ModelInfo::from_mjcf(&a))
        .expect_err("a two-file cycle");
    assert_eq!(d.code, Code::E0302, "{d}");
    let at = d.location.as_ref().expect("located");
    assert_eq!(at.file.path, b, "{d}");
    assert_eq!(lc(&d), find_lc(b_text, "./a.xml"), "{d}");
    let read: Vec<_> = reader.files().iter().map(|f| f.path.clone()).collect();
    assert_eq!(read, vec![a.clone(), b.clone()]);

    // A chain of distinct files one deeper than the limit.
    let n = envspec::limits::MAX_INCLUDE_DEPTH + 1;
    for i in 0..=n {
        let body = if i < n {
            format!("<mujoco>\n<include file=\"d{}.xml\"/>\n</mujoco>\n", i + 1)
        } else {
            "<mujoco/>\n".to_string()
        };
        s.write(&format!("d{i}.xml"), &body);
    }
    let d = ModelInfo::from_mjcf(&s.0.join("d0.xml")).expect_err("too deep");
    assert_eq!(d.code, Code::E0110, "{d}");
    assert_eq!(
        d.location.as_ref().expect("located").file.path,
        s.0.join(format!("d{}.xml", n - 1))
    );
    // One level less is read.
    s.write(&format!("d{}.xml", n - 1), "<mujoco/>\n");
    ModelInfo::from_mjcf(&s.0.join("d0.xml")).expect("at the limit");
}
