//! `motion_launch [CONFIG.yaml] [--duration S] [--check]` (default `launch-configs/demo.yaml`).

fn main() {
    std::process::exit(motion_runtime::launch::main_with(
        "motion_launch",
        motion_launch::KINDS,
        "launch-configs/demo.yaml",
    ));
}
