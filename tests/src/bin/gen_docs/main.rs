//! Rewrites the generated parts of the user guide (`docs/*.md`): launch-config key tables and
//! error-id tables from the code (see `system_tests::docs`). `tests/tests/docs.rs` checks
//! that the committed pages are up to date.

fn main() {
    let root = system_tests::workspace();
    for (path, old, new) in system_tests::docs::render(&root) {
        if old != new {
            std::fs::write(&path, new).expect("write page");
            println!("updated {}", path.display());
        }
    }
}
