// A build-time override of a parameter the spec does not declare, and one of the wrong type.
envc_codegen::env!(
    pub MyAnt = "../../specs/gymnasium/ant.toml",
    ctrl_cost_weigth = 0.1,
    healthy_z_range = true
);

fn main() {}
