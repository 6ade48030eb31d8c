//! Fuzz targets (issue 33 §2): everything that parses input from outside the process, each a
//! function of arbitrary bytes that must return (an error is fine) and never panic or hang.
//! The same functions serve the coverage-guided campaign (`fuzz/`, cargo-afl) and the corpus
//! replay of the test command (`tests/tests/fuzz_corpus.rs`, every file of
//! `fuzz/corpus/<target>/`).

use motion_runtime::launch;
use motion_runtime::ros_args::params_text;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// A fuzz target: arbitrary bytes in, nothing out; must not panic or hang.
pub type Target = fn(&[u8]);

/// The targets by name (the corpus directories are named the same).
pub const TARGETS: &[(&str, Target)] = &[
    ("launch_config", launch_config),
    ("command_line", command_line),
    ("params_yaml", params_yaml),
    ("cdr_inbound", cdr_inbound),
];

/// A launch config (YAML text) through the launcher's check: its structure, the common keys of
/// each node entry and each node kind's own config check (`motion_launch --check`).
pub fn launch_config(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(entries) = launch::parse(text, "fuzz.yaml", motion_launch::KINDS) else {
        return;
    };
    for e in entries {
        if let Some(kind) = motion_launch::KINDS.iter().find(|k| k.kind == e.kind) {
            let _ = (kind.check)(&e.common, e.engine, &e.location);
        }
    }
}

/// A command line (arguments separated by NUL bytes) as the launcher reads it: options,
/// `--ros-args` with remaps and parameters, the recording options. `--params-file` names a file
/// to read; here its argument is dropped (the file's text is `params_yaml`'s target).
pub fn command_line(data: &[u8]) {
    let args: Vec<String> = data
        .split(|b| *b == 0)
        .map(|a| String::from_utf8_lossy(a).into_owned())
        .collect();
    let mut kept = Vec::with_capacity(args.len());
    let mut it = args.into_iter();
    while let Some(a) = it.next() {
        if a == "--params-file" {
            it.next();
            continue;
        }
        kept.push(a);
    }
    let _ = launch::parse_args_from(kept, "usage");
}

/// A ROS parameter file's text (`--params-file`).
pub fn params_yaml(data: &[u8]) {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = params_text(text, "fuzz.yaml");
    }
}

/// CDR bytes of a request or goal, as a client sends them: the first byte picks the type (of
/// every service request and action goal of `motion_msgs`), the rest is decoded as DDS hands
/// it to ros2-client (CDR little endian, after the encapsulation header).
pub fn cdr_inbound(data: &[u8]) {
    let Some((&pick, payload)) = data.split_first() else {
        return;
    };
    struct Decode<'a> {
        pick: usize,
        seen: usize,
        payload: &'a [u8],
    }
    impl motion_msgs::InboundVisitor for Decode<'_> {
        fn visit<T: DeserializeOwned + Serialize + Default + std::fmt::Debug>(
            &mut self,
            _: &'static str,
        ) {
            if self.seen == self.pick {
                let _ = decode::<T>(self.payload);
            }
            self.seen += 1;
        }
    }
    // Counted once: this runs for every input of a campaign.
    static COUNT: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    let count = *COUNT.get_or_init(inbound_type_count);
    let mut v = Decode {
        pick: pick as usize % count,
        seen: 0,
        payload,
    };
    motion_msgs::visit_inbound(&mut v);
}

/// How many inbound types there are.
pub fn inbound_type_count() -> usize {
    struct Count(usize);
    impl motion_msgs::InboundVisitor for Count {
        fn visit<T: DeserializeOwned + Serialize + Default + std::fmt::Debug>(
            &mut self,
            _: &'static str,
        ) {
            self.0 += 1;
        }
    }
    let mut c = Count(0);
    motion_msgs::visit_inbound(&mut c);
    c.0
}

/// Decodes CDR little endian as the nodes' readers do.
pub fn decode<T: DeserializeOwned>(payload: &[u8]) -> Result<T, String> {
    use rustdds::no_key::DeserializerAdapter;
    rustdds::CDRDeserializerAdapter::<T>::from_bytes(
        payload,
        rustdds::RepresentationIdentifier::CDR_LE,
    )
    .map_err(|e| e.to_string())
}

/// Seeds of `cdr_inbound`'s corpus: for every inbound type, its index and the CDR of its
/// default value (what `fuzz/corpus/cdr_inbound/` starts from).
pub fn cdr_seeds() -> Vec<(&'static str, Vec<u8>)> {
    struct Seeds(Vec<(&'static str, Vec<u8>)>);
    impl motion_msgs::InboundVisitor for Seeds {
        fn visit<T: DeserializeOwned + Serialize + Default + std::fmt::Debug>(
            &mut self,
            name: &'static str,
        ) {
            use rustdds::no_key::SerializerAdapter;
            let mut bytes = vec![self.0.len() as u8];
            let cdr = rustdds::CDRSerializerAdapter::<T>::to_bytes(&T::default())
                .expect("a default value encodes");
            bytes.extend_from_slice(&cdr);
            self.0.push((name, bytes));
        }
    }
    let mut s = Seeds(Vec::new());
    motion_msgs::visit_inbound(&mut s);
    s.0
}
