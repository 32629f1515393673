//! `sensordata[...]`: the model's `<sensor>` values by sensor name, against MuJoCo's own
//! `data.sensordata` for the same model and steps, recorded with MuJoCo 3.17.0's Python bindings
//! into fixtures/sensors/box_sensors.json:
//!
//! ```python
//! m = mujoco.MjModel.from_xml_path("tests/fixtures/sensors/box_sensors.xml"); d = mujoco.MjData(m)
//! mujoco.mj_resetData(m, d); mujoco.mj_forward(m, d); rows = [d.sensordata.copy()]
//! for _ in range(60):
//!     for _ in range(5): mujoco.mj_step(m, d)
//!     rows.append(d.sensordata.copy())
//! ```

use std::path::Path;

use envc::Env;

#[test]
fn sensor_values_are_mujocos_by_name() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/sensors");
    let rec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("box_sensors.json")).unwrap())
            .unwrap();
    let rows: Vec<Vec<f64>> = rec["sensordata"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| envc_tests::unhex(r.as_str().unwrap()))
        .collect();
    let mut env = Env::from_spec_file(dir.join("box_sensors.toml"), &[]).unwrap();
    let names = env.spec().obs_names();
    assert_eq!(
        names[..5],
        [
            "sensordata[pad]",
            "sensordata[accel:0]",
            "sensordata[accel:1]",
            "sensordata[accel:2]",
            "sensordata[where:0]"
        ]
    );
    let bits = |a: &[f64]| a.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(env.reset(Some(0)).0), bits(&rows[0]));
    for (t, row) in rows.iter().enumerate().skip(1) {
        let s = env.step(&[]).unwrap();
        assert_eq!(bits(s.obs), bits(row), "step {t}");
    }
    // The box rests on the pad by the end: the touch sensor reads its weight.
    assert!(rows.last().unwrap()[0] > 2.0);
}
