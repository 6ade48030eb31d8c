//! `pickplace_node [CONFIG.yaml]`: runs the pickplace_node entries of a launch config.

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "pickplace_node",
        &[pickplace_node::NODE_KIND],
        "launch-configs/demo.yaml",
    ));
}
