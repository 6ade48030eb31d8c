//! The generated parts of the user guide (`docs/*.md`): launch-config key tables (key,
//! default, meaning) and error-id tables, taken from the code itself (field doc comments,
//! `Default` values, error constants), so the guide cannot drift from what the nodes accept.
//!
//! A page marks each generated part with `<!-- BEGIN GENERATED name -->` ...
//! `<!-- END GENERATED name -->`; `cargo run -p system_tests --bin gen_docs` rewrites them,
//! and `tests/tests/docs.rs` fails while a page is stale.

use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// One config struct of a table: where it is, its name, the YAML prefix of its keys, and its
/// default values (a serialized default or sample instance).
struct KeySource {
    file: &'static str,
    name: &'static str,
    prefix: &'static str,
    defaults: serde_yaml::Value,
}

fn yaml<T: Serialize>(t: &T) -> serde_yaml::Value {
    serde_yaml::to_value(t).expect("config serializes")
}

/// The defaults of a struct with required keys: `required` (YAML) read as the nodes read a
/// launch config, then written back, so every left-out key shows serde's default.
fn sample<T: Serialize + serde::de::DeserializeOwned>(required: &str) -> serde_yaml::Value {
    let t: T = serde_yaml::from_str(required).unwrap_or_else(|e| panic!("{required}: {e}"));
    yaml(&t)
}

/// A field of a config struct: its key, doc comment and whether it may be left out.
struct Field {
    key: String,
    doc: String,
    optional: bool,
}

/// The fields of `pub struct name` in Rust source `text`, with their `///` comments.
fn struct_fields(text: &str, name: &str) -> Vec<Field> {
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().starts_with(&format!("pub struct {name} ")))
        .unwrap_or_else(|| panic!("struct {name} not found"));
    // `#[serde(default)]` on the struct: every field may be left out.
    let all_default = lines[..start]
        .iter()
        .rev()
        .take_while(|l| l.starts_with("#[") || l.starts_with("///"))
        .any(|l| l.starts_with("#[serde(") && l.contains("default"));
    let mut out = Vec::new();
    let (mut doc, mut field_default) = (Vec::<String>::new(), false);
    for l in &lines[start + 1..] {
        let t = l.trim();
        if l.starts_with('}') {
            break;
        }
        if let Some(d) = t.strip_prefix("///") {
            doc.push(d.trim().to_string());
        } else if t.starts_with("#[serde(") {
            field_default |= t.contains("default");
        } else if let Some(rest) = t.strip_prefix("pub ") {
            let key = rest.split(':').next().unwrap_or("").trim().to_string();
            let ty = rest.split_once(':').map(|x| x.1).unwrap_or("");
            out.push(Field {
                key,
                doc: doc.join(" ").replace("\\[", "[").replace("\\]", "]"),
                optional: all_default || field_default || ty.trim().starts_with("Option<"),
            });
            doc.clear();
            field_default = false;
        } else if t.is_empty() {
            doc.clear();
        }
    }
    out
}

/// A default value as it is written in YAML (inline).
fn inline(v: &serde_yaml::Value) -> String {
    match v {
        serde_yaml::Value::Null => "none".into(),
        serde_yaml::Value::Mapping(m) if m.is_empty() => "{}".into(),
        serde_yaml::Value::Sequence(s) if s.is_empty() => "[]".into(),
        serde_yaml::Value::Mapping(m)
            if m.len() <= 8 && m.values().all(|v| !v.is_mapping() && !v.is_sequence()) =>
        {
            let j = serde_json::to_string(v).unwrap_or_default();
            j.replace(',', ", ").replace(':', ": ")
        }
        serde_yaml::Value::Mapping(_) => "(keys below)".into(),
        other => {
            let j = serde_json::to_string(other).unwrap_or_default();
            j.replace(',', ", ")
        }
    }
}

fn key_table(root: &Path, sources: &[KeySource]) -> String {
    let mut s = String::from("| key | default | meaning |\n|---|---|---|\n");
    for src in sources {
        let text = std::fs::read_to_string(root.join(src.file)).expect(src.file);
        for f in struct_fields(&text, src.name) {
            let default = if f.optional {
                src.defaults
                    .get(&f.key)
                    .map(inline)
                    .unwrap_or_else(|| "none".into())
            } else {
                "required".into()
            };
            let doc = rustdoc_links(&f.doc).replace('|', "\\|");
            s.push_str(&format!(
                "| `{}{}` | {} | {} |\n",
                src.prefix,
                f.key,
                default.replace('|', "\\|"),
                doc
            ));
        }
    }
    s
}

/// Rustdoc links (`[`Name`]`, `[`a`](b)`) as plain code spans.
fn rustdoc_links(doc: &str) -> String {
    let mut out = String::new();
    let mut rest = doc;
    while let Some(i) = rest.find("[`") {
        let Some(j) = rest[i..].find("`]") else { break };
        out.push_str(&rest[..i]);
        out.push_str(&rest[i + 1..i + j + 1]);
        rest = &rest[i + j + 2..];
        // Drop a link target `(...)` right after.
        if rest.starts_with('(') {
            if let Some(k) = rest.find(')') {
                rest = &rest[k + 1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// `pub const NAME: ErrorId = ErrorId(..)` items of a file, with their comments.
fn error_consts(text: &str) -> Vec<(String, u32, String)> {
    let mut out = Vec::new();
    let mut doc: Vec<String> = Vec::new();
    for l in text.lines() {
        let t = l.trim();
        if let Some(d) = t.strip_prefix("///") {
            doc.push(d.trim().to_string());
            continue;
        }
        if let Some(rest) = t.strip_prefix("pub const ") {
            if let Some((name, value)) = rest.split_once(": ErrorId = ErrorId(") {
                let v = value.trim_end_matches(");").replace('_', "");
                let id = match v.strip_prefix("0x") {
                    Some(h) => u32::from_str_radix(h, 16),
                    None => v.parse(),
                }
                .unwrap_or_else(|_| panic!("error id {v}"));
                out.push((name.to_string(), id, doc.join(" ")));
            }
        }
        doc.clear();
    }
    out
}

fn error_table(root: &Path, files: &[&str]) -> String {
    let mut s = String::from("| id | hex | name | meaning |\n|---|---|---|---|\n");
    for f in files {
        let text = std::fs::read_to_string(root.join(f)).expect(f);
        for (name, id, doc) in error_consts(&text) {
            if id == 0 {
                continue;
            }
            let doc = rustdoc_links(&doc).replace('|', "\\|");
            s.push_str(&format!("| {id} | 0x{id:04X} | `{name}` | {doc} |\n"));
        }
    }
    s
}

/// Every generated part by name.
pub fn generated(root: &Path) -> BTreeMap<&'static str, String> {
    use axis_engine::platform::{AxisPlatformConfig, PlatformConfig};
    let planar = planar_engine::PlanarConfig::default();
    let pp = pickplace_engine::PickPlaceConfig::default();
    const AXIS_CFG: &str = "nodes/axis_node/single_axis/src/config.rs";
    const PLANAR_CFG: &str = "nodes/planar_node/engine/src/config.rs";
    const PP_CFG: &str = "nodes/pickplace_node/engine/src/config.rs";
    const PP_PAR: &str = "nodes/pickplace_node/engine/src/params.rs";
    let ks = |file, name, prefix, defaults| KeySource {
        file,
        name,
        prefix,
        defaults,
    };
    let mut m = BTreeMap::new();
    m.insert(
        "keys-common",
        key_table(
            root,
            &[ks(
                "nodes/runtime/src/host.rs",
                "CommonConfig",
                "",
                yaml(&motion_runtime::CommonConfig::default()),
            )],
        ),
    );
    m.insert(
        "keys-axis",
        key_table(
            root,
            &[ks(
                AXIS_CFG,
                "AxisConfig",
                "axes.<axis>.",
                yaml(&axis_engine::AxisConfig::default()),
            )],
        ),
    );
    m.insert(
        "keys-axis-platform",
        key_table(
            root,
            &[
                ks(
                    "nodes/axis_node/isg_platform/src/config.rs",
                    "PlatformConfig",
                    "platform.",
                    yaml(&PlatformConfig::default()),
                ),
                ks(
                    "nodes/axis_node/isg_platform/src/config.rs",
                    "AxisPlatformConfig",
                    "platform.axes.<axis>.",
                    yaml(&AxisPlatformConfig::default()),
                ),
            ],
        ),
    );
    m.insert(
        "keys-axis-ca",
        key_table(
            root,
            &[ks(
                "nodes/axis_node/collision_avoidance/src/types.rs",
                "CaGroupConfig",
                "ca_groups.<group>.",
                yaml(&axis_engine::ca::CaGroupConfig::default()),
            )],
        ),
    );
    m.insert(
        "keys-planar",
        key_table(
            root,
            &[
                ks(PLANAR_CFG, "PlanarConfig", "", yaml(&planar)),
                ks(
                    PLANAR_CFG,
                    "EnvironmentConfig",
                    "environment.",
                    yaml(&planar.environment),
                ),
                ks(
                    PLANAR_CFG,
                    "PartConfig",
                    "parts[].",
                    sample::<planar_engine::PartConfig>(
                        "{name: p, oid: 1, tiles: [], positions: {}}",
                    ),
                ),
                ks(
                    PLANAR_CFG,
                    "PartPositionConfig",
                    "parts[].positions.<index>.",
                    serde_yaml::Value::Null,
                ),
                ks(
                    PLANAR_CFG,
                    "MoverConfig",
                    "movers[].",
                    sample::<planar_engine::MoverConfig>("{name: m}"),
                ),
                ks(
                    PLANAR_CFG,
                    "InitialPose",
                    "movers[].initial_pose.",
                    yaml(&planar_engine::InitialPose::default()),
                ),
                ks(
                    PLANAR_CFG,
                    "GroupConfig",
                    "groups[].",
                    sample::<planar_engine::GroupConfig>("{name: g}"),
                ),
                ks(
                    PLANAR_CFG,
                    "VirtualAxisConfig",
                    "axes[].",
                    sample::<planar_engine::VirtualAxisConfig>("{name: x}"),
                ),
                ks(
                    PLANAR_CFG,
                    "TrackConfig",
                    "tracks[].",
                    sample::<planar_engine::TrackConfig>("{name: t}"),
                ),
                ks(
                    PLANAR_CFG,
                    "TrackLineConfig",
                    "tracks[].geometry[].line.",
                    serde_yaml::Value::Null,
                ),
                ks(
                    PLANAR_CFG,
                    "TrackCircleConfig",
                    "tracks[].geometry[].circle.",
                    serde_yaml::Value::Null,
                ),
                ks(
                    PLANAR_CFG,
                    "TrackLinkAdvancedConfig",
                    "tracks[].links[].",
                    serde_yaml::Value::Null,
                ),
            ],
        ),
    );
    m.insert(
        "keys-pickplace",
        key_table(
            root,
            &[
                ks(PP_CFG, "PickPlaceConfig", "", yaml(&pp)),
                ks(
                    PP_CFG,
                    "AxisConfig",
                    "axes.<axis>.",
                    yaml(&pickplace_engine::AxisConfig::default()),
                ),
                ks(
                    PP_CFG,
                    "BeltConfig",
                    "belts.<n>.",
                    yaml(&pickplace_engine::BeltConfig::default()),
                ),
                ks(
                    PP_PAR,
                    "ConveyorBeltPar",
                    "belts.<n>.params.",
                    yaml(&pickplace_engine::ConveyorBeltPar::default()),
                ),
                ks(PP_PAR, "ScPar", "params.", yaml(&pp.params)),
            ],
        ),
    );
    m.insert(
        "errors-common",
        error_table(root, &["nodes/motion_core/src/error_id.rs"]),
    );
    m.insert(
        "errors-axis",
        error_table(root, &["nodes/axis_node/single_axis/src/error_ids.rs"]),
    );
    m.insert(
        "errors-axis-ca",
        error_table(root, &["nodes/axis_node/collision_avoidance/src/errors.rs"]),
    );
    m.insert(
        "errors-axis-platform",
        error_table(root, &["nodes/axis_node/axis_groups/src/ids.rs"]),
    );
    m.insert(
        "errors-planar",
        error_table(root, &["nodes/planar_node/engine/src/errors.rs"]),
    );
    m.insert(
        "errors-pickplace",
        error_table(root, &["nodes/pickplace_node/engine/src/error_ids.rs"]),
    );
    m
}

/// The pages of the guide with their generated parts filled in: (path, new text) for each
/// page under `docs/`. Panics on a marker without a generator or an unclosed marker.
pub fn render(root: &Path) -> Vec<(std::path::PathBuf, String, String)> {
    let parts = generated(root);
    let mut out = Vec::new();
    let mut dir: Vec<_> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    dir.sort();
    for path in dir {
        let old = std::fs::read_to_string(&path).expect("page");
        let mut new = String::new();
        let mut rest = old.as_str();
        while let Some(i) = rest.find("<!-- BEGIN GENERATED ") {
            let head_end = i + rest[i..].find("-->").expect("marker end") + 3;
            let name = rest[i + "<!-- BEGIN GENERATED ".len()..head_end - 3].trim();
            let end_marker = format!("<!-- END GENERATED {name} -->");
            let j = rest[head_end..]
                .find(&end_marker)
                .unwrap_or_else(|| panic!("{}: {end_marker} missing", path.display()))
                + head_end;
            let body = parts
                .get(name)
                .unwrap_or_else(|| panic!("{}: no generated part '{name}'", path.display()));
            new.push_str(&rest[..head_end]);
            new.push('\n');
            new.push_str(body);
            rest = &rest[j..];
        }
        new.push_str(rest);
        out.push((path, old, new));
    }
    out
}
