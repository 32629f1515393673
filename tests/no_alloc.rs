//! `step` and `reset` allocate nothing after construction (counted with a per-thread counting
//! allocator, so other test threads do not interfere).

use envc_tests::allocations;

#[test]
fn step_and_reset_do_not_allocate() {
    let goal = envc::registry::examples()
        .into_iter()
        .filter(|(id, _)| id == "ReacherGoal-v0");
    // The joystick (commands, PD actions, legged terms) over the shared Go1.
    let go1 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/models/unitree_go1/scene.xml"
    );
    let joystick = envc::registry::examples()
        .into_iter()
        .filter(|(id, _)| id == "Go1Joystick-v0");
    for (id, path) in envc::registry::bundled()
        .into_iter()
        .chain(goal)
        .chain(joystick)
    {
        let xml = envc::Override::text("xml_file", go1);
        let over = if id == "Go1Joystick-v0" {
            vec![xml]
        } else {
            vec![]
        };
        let mut env = envc::Env::from_spec_file(&path, &over).unwrap();
        env.reset(Some(0));
        let a = vec![0.1; env.act_dim()];
        let a32 = vec![0.1f32; env.act_dim()];
        let n = allocations(|| {
            for i in 0..200 {
                let s = if i % 2 == 0 {
                    env.step(&a).unwrap()
                } else {
                    env.step_f32(&a32).unwrap()
                };
                let (done, r) = (s.terminated || s.truncated, s.reward);
                std::hint::black_box(r);
                if done {
                    env.reset(None);
                }
                if i % 50 == 0 {
                    env.reset(Some(i));
                }
            }
        });
        assert_eq!(n, 0, "{id}: {n} allocations in 200 steps");
    }
}

/// A maze step (the robot's step, its goal terms, `success`, the goal update) allocates nothing.
#[test]
fn maze_step_does_not_allocate() {
    for id in ["PointMaze_UMaze-v3", "PointMaze_OpenDense-v3"] {
        let over = [envc::Override::text("reset_target", "true")];
        let mut env = envc::maze::MazeEnv::make(id, &over).unwrap();
        env.reset(Some(0), None).unwrap();
        let a = vec![1.0; env.act_dim()];
        let mut r = [0.0; 4];
        let n = allocations(|| {
            for i in 0..300 {
                let s = env.step(&a).unwrap();
                std::hint::black_box(s.reward);
                if s.terminated || s.truncated {
                    env.reset(None, None).unwrap();
                }
                let g = env.goal();
                env.compute_reward(&[g, [0.0; 2], g, g], &[g, g, [1.0; 2], [9.0; 2]], &mut r);
                std::hint::black_box(env.compute_terminated(g, g));
                if i % 100 == 0 {
                    env.reset(Some(i), None).unwrap();
                }
            }
        });
        assert_eq!(n, 0, "{id}: {n} allocations in 300 steps");
    }
}
