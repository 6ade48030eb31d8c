//! AFL++ target: `system_tests::fuzz::command_line` (fuzz/README.md).
fn main() {
    afl::fuzz!(|data: &[u8]| system_tests::fuzz::command_line(data));
}
