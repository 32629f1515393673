//! Inputs that are not what they seem: devices, FIFOs and oversized specs, NUL bytes in names.

use std::process::Command;

use super::{Scratch, envc, refused, s};

#[test]
fn devices_and_fifos_are_not_read() {
    let dir = Scratch::new("devices");
    let spec = dir.spec("hopper.toml", &[("model.xml", "/dev/zero")], &[]);
    let text = refused(&envc(&["check", "--compile", s(&spec)]), "E0301");
    assert!(text.contains("device, not a regular file"), "{text}");
    let text = refused(&envc(&["check", "/dev/zero"]), "E0600");
    assert!(text.contains("device, not a regular file"), "{text}");
    // A FIFO would block the open until a writer comes.
    let fifo = dir.0.join("fifo.toml");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let text = refused(&envc(&["check", s(&fifo)]), "E0600");
    assert!(text.contains("FIFO"), "{text}");
    // A spec over the size limit (a long comment keeps it valid TOML).
    let big = dir.0.join("big.toml");
    let hopper = std::fs::read_to_string(dir.spec("hopper.toml", &[], &[])).unwrap();
    std::fs::write(&big, format!("{hopper}\n#{}\n", "x".repeat(5 << 20))).unwrap();
    let text = refused(&envc(&["check", s(&big)]), "E0110");
    assert!(text.contains("4 MiB"), "{text}");
}

#[test]
fn a_nul_byte_in_an_added_element_name_is_a_spec_error_not_a_panic() {
    let dir = Scratch::new("nul-names");
    let sections = [
        "[sites.\"a\\u0000b\"]\nbody = \"torso\"\n",
        "[bodies.\"a\\u0000b\"]\npos = [0.0, 0.0, 1.0]\n",
        "[bodies.g]\njoints = { \"x\\u0000y\" = \"slide x\" }\n",
        "[geoms.\"a\\u0000b\"]\nbody = \"torso\"\ntype = \"box\"\nsize = [0.1, 0.1, 0.1]\n",
        "[cameras.\"a\\u0000b\"]\npos = [0.0, -1.0, 1.0]\n",
        "[lights.\"a\\u0000b\"]\npos = [0.0, 0.0, 2.0]\n",
        "[actuators.\"a\\u0000b\"]\njoint = \"rootx\"\n",
        "[keyframes.\"a\\u0000b\"]\njoints = { rootz = 0.0 }\n",
    ];
    for (i, section) in sections.iter().enumerate() {
        let spec = dir.spec("hopper.toml", &[], &[]);
        let mut text = std::fs::read_to_string(&spec).unwrap();
        text.push('\n');
        text.push_str(section);
        let spec = dir.0.join(format!("nul{i}.toml"));
        std::fs::write(&spec, text).unwrap();
        for args in [
            &["check", "--compile", s(&spec)][..],
            &["show", s(&spec)],
            &["run", s(&spec), "--episodes", "1"],
        ] {
            let text = refused(&envc(args), "E0102");
            assert!(text.contains("contains a NUL byte"), "{section}: {text}");
        }
    }
}
