//! The fuzz corpus replayed (issue 33 §2): every file of `fuzz/corpus/<target>/` through its
//! target (`tests/src/fuzz.rs`), the smoke run of the coverage-guided campaign
//! (`fuzz/README.md`). None may panic; each target has a corpus. The `cdr_inbound` seeds are
//! the default value of every service request and action goal, one file each: a new interface
//! without its seed fails here (`MOTION_WRITE_FUZZ_SEEDS=1` writes the missing ones).

use system_tests::{fuzz, workspace};

#[test]
fn every_corpus_file_passes_its_target() {
    for (name, target) in fuzz::TARGETS {
        let dir = workspace().join("fuzz/corpus").join(name);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        assert!(!files.is_empty(), "{name}: no corpus in {}", dir.display());
        for f in &files {
            let data = std::fs::read(f).unwrap();
            let run = std::panic::catch_unwind(|| target(&data));
            assert!(run.is_ok(), "{name}: {} panics", f.display());
        }
        println!("{name}: {} inputs", files.len());
    }
}

#[test]
fn every_inbound_type_has_its_cdr_seed() {
    let dir = workspace().join("fuzz/corpus/cdr_inbound");
    let seeds = fuzz::cdr_seeds();
    assert_eq!(seeds.len(), fuzz::inbound_type_count());
    let mut missing = Vec::new();
    for (name, bytes) in seeds {
        let file = dir.join(format!("seed_{}", name.replace('/', "_")));
        if std::fs::read(&file).ok().as_deref() != Some(&bytes[..]) {
            if std::env::var("MOTION_WRITE_FUZZ_SEEDS").as_deref() == Ok("1") {
                std::fs::write(&file, &bytes).unwrap();
            } else {
                missing.push(file.display().to_string());
            }
        }
    }
    assert!(missing.is_empty(), "missing or stale seeds: {missing:?}");
}
