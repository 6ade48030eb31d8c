//! AFL++ target: `system_tests::fuzz::params_yaml` (fuzz/README.md).
fn main() {
    afl::fuzz!(|data: &[u8]| system_tests::fuzz::params_yaml(data));
}
