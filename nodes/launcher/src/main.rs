//! `motion_launch [CONFIG.yaml] [--duration S] [--check]` (default `launch-configs/demo.yaml`).

/// See [`motion_runtime::rt::Allocator`].
#[global_allocator]
static ALLOCATOR: motion_runtime::rt::Allocator = motion_runtime::rt::Allocator;

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "motion_launch",
        motion_launch::KINDS,
        "launch-configs/demo.yaml",
    ));
}
