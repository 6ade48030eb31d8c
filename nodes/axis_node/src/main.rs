//! `axis_node [CONFIG.yaml]`: runs the axis_node entries of a launch config.

/// See [`motion_runtime::rt::Allocator`].
#[global_allocator]
static ALLOCATOR: motion_runtime::rt::Allocator = motion_runtime::rt::Allocator;

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "axis_node",
        &[axis_node::NODE_KIND],
        "launch-configs/demo.yaml",
    ));
}
