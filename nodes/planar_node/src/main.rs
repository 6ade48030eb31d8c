//! `planar_node [CONFIG.yaml]`: runs the planar_node entries of a launch config.

/// See [`motion_runtime::rt::Allocator`].
#[global_allocator]
static ALLOCATOR: motion_runtime::rt::Allocator = motion_runtime::rt::Allocator;

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "planar_node",
        &[planar_node::NODE_KIND],
        "launch-configs/demo.yaml",
    ));
}
