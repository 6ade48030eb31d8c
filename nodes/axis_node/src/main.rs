//! `axis_node [CONFIG.yaml]`: runs the axis_node entries of a launch config.

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "axis_node",
        &[axis_node::NODE_KIND],
        "launch-configs/demo.yaml",
    ));
}
