//! AFL++ target: `system_tests::fuzz::cdr_inbound` (fuzz/README.md).
fn main() {
    afl::fuzz!(|data: &[u8]| system_tests::fuzz::cdr_inbound(data));
}
