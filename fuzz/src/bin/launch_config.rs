//! AFL++ target: `system_tests::fuzz::launch_config` (fuzz/README.md).
fn main() {
    afl::fuzz!(|data: &[u8]| system_tests::fuzz::launch_config(data));
}
