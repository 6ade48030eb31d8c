//! ROS command-line arguments, as ROS users pass them: `CONFIG --ros-args [ARGS] [--]`, the
//! subset that applies to our nodes (issue 13):
//! - `-p` / `--param [NODE:]NAME:=VALUE`: overrides a key of the matching node entries of the
//!   launch config (all entries without `NODE:`); `VALUE` is YAML, dotted names reach nested
//!   keys (`axes.x.max_velocity:=500`). Applied before validation, so an override is checked
//!   exactly as the config is.
//! - `--params-file FILE`: ROS parameter YAML (`<node>|/<ns>/<node>|/**: ros__parameters:
//!   {...}`), merged the same way, before the `-p` overrides.
//! - `-r` / `--remap [NODE:]FROM:=TO`: `__node:=NAME` and `__ns:=/NS` rename the node(s);
//!   any other `FROM` (absolute, relative to the namespace, or `~/` private) renames that
//!   topic, service or action wherever a node resolves it.
//!
//! Anything else after `--ros-args` is refused with a clear message (exit code 2).

use serde_yaml::{Mapping, Value};
use std::sync::OnceLock;

/// One `[NODE:]FROM:=TO` remap.
#[derive(Clone, Debug, PartialEq)]
pub struct Remap {
    /// Only for this node (its name), or every node.
    pub node: Option<String>,
    /// The name as the node resolves it (`/abs`, `rel` or `~/private`).
    pub from: String,
    /// The new name.
    pub to: String,
}

/// The parsed ROS arguments.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RosArgs {
    /// `-r` remaps in order.
    pub remaps: Vec<Remap>,
    /// Parameter files in order, then `-p` overrides: (node or None, dotted name, value).
    pub params: Vec<(Option<String>, String, Value)>,
}

/// Splits `[NODE:]LHS:=RHS`.
fn split_assignment(arg: &str, what: &str) -> Result<(Option<String>, String, String), String> {
    let (lhs, rhs) = arg
        .split_once(":=")
        .ok_or_else(|| format!("{what} '{arg}': expected [NODE:]NAME:=VALUE"))?;
    let (node, name) = match lhs.split_once(':') {
        Some((n, rest)) => (Some(n.trim_start_matches('/').to_string()), rest),
        None => (None, lhs),
    };
    if name.is_empty() {
        return Err(format!("{what} '{arg}': empty name"));
    }
    Ok((node, name.to_string(), rhs.to_string()))
}

impl RosArgs {
    /// Parses the tokens after `--ros-args` (up to `--`).
    pub fn parse(tokens: &[String]) -> Result<Self, String> {
        let mut a = RosArgs::default();
        let mut overrides = Vec::new();
        let mut it = tokens.iter();
        while let Some(t) = it.next() {
            let mut value = |opt: &str| {
                it.next()
                    .cloned()
                    .ok_or_else(|| format!("--ros-args: {opt} needs an argument"))
            };
            match t.as_str() {
                "-p" | "--param" => {
                    let arg = value(t)?;
                    let (node, name, v) = split_assignment(&arg, "-p")?;
                    let v: Value = serde_yaml::from_str(&v)
                        .map_err(|e| format!("-p '{arg}': the value is not YAML: {e}"))?;
                    overrides.push((node, name, v));
                }
                "-r" | "--remap" => {
                    let arg = value(t)?;
                    let (node, from, to) = split_assignment(&arg, "-r")?;
                    match from.as_str() {
                        "__node" | "__name" => {
                            a.params.push((node, "name".into(), Value::String(to)))
                        }
                        "__ns" => a.params.push((node, "namespace".into(), Value::String(to))),
                        _ => a.remaps.push(Remap { node, from, to }),
                    }
                }
                "--params-file" => {
                    let file = value(t)?;
                    a.params.extend(params_file(&file)?);
                }
                other => {
                    return Err(format!(
                        "--ros-args: unsupported argument '{other}' (supported: -p/--param \
                         [NODE:]NAME:=VALUE, -r/--remap [NODE:]FROM:=TO, --params-file FILE)"
                    ))
                }
            }
        }
        a.params.extend(overrides);
        Ok(a)
    }

    /// Applies the parameters to one node entry of the launch config (`kind` gives the
    /// default name), before it is validated.
    pub fn apply_params(&self, entry: &mut Mapping, kind: &str) {
        for (node, name, value) in &self.params {
            if let Some(n) = node {
                if !matches_node(n, entry, kind) {
                    continue;
                }
            }
            set_dotted(entry, name, value.clone());
        }
    }
}

/// Does `pattern` (`name`, `ns/name` without the leading slash, or `**`) name this entry?
fn matches_node(pattern: &str, entry: &Mapping, kind: &str) -> bool {
    if pattern == "**" {
        return true;
    }
    let name = entry.get("name").and_then(Value::as_str).unwrap_or(kind);
    let ns = entry
        .get("namespace")
        .and_then(Value::as_str)
        .unwrap_or("/")
        .trim_matches('/');
    pattern == name || (!ns.is_empty() && pattern == format!("{ns}/{name}"))
}

fn set_dotted(map: &mut Mapping, dotted: &str, value: Value) {
    let mut parts = dotted.split('.').peekable();
    let mut cur = map;
    while let Some(p) = parts.next() {
        let key = Value::String(p.to_string());
        if parts.peek().is_none() {
            cur.insert(key, value);
            return;
        }
        if !cur.get(&key).is_some_and(Value::is_mapping) {
            cur.insert(key.clone(), Value::Mapping(Mapping::new()));
        }
        cur = cur
            .get_mut(&key)
            .and_then(Value::as_mapping_mut)
            .expect("just made a mapping");
    }
}

/// Reads a ROS parameter file into (node, dotted name, value) entries.
fn params_file(file: &str) -> Result<Vec<(Option<String>, String, Value)>, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("--params-file {file}: {e}"))?;
    params_text(&text, file)
}

/// A ROS parameter file's text (`file` names it in messages) as (node, dotted name, value).
pub fn params_text(text: &str, file: &str) -> Result<Vec<(Option<String>, String, Value)>, String> {
    let root: Value =
        serde_yaml::from_str(text).map_err(|e| format!("--params-file {file}: {e}"))?;
    let nodes = root
        .as_mapping()
        .ok_or_else(|| format!("--params-file {file}: expected a mapping of node names"))?;
    let mut out = Vec::new();
    for (node, body) in nodes {
        let node = node
            .as_str()
            .ok_or_else(|| format!("--params-file {file}: node names must be strings"))?;
        let params = body
            .get("ros__parameters")
            .and_then(Value::as_mapping)
            .ok_or_else(|| {
                format!("--params-file {file}: {node}: expected 'ros__parameters:' with a mapping")
            })?;
        let node = node.trim_start_matches('/').to_string();
        flatten(params, "", &mut |name, v| {
            out.push((Some(node.clone()), name, v))
        });
    }
    Ok(out)
}

fn flatten(m: &Mapping, prefix: &str, out: &mut impl FnMut(String, Value)) {
    for (k, v) in m {
        let k = match k {
            Value::String(s) => s.clone(),
            other => serde_yaml::to_string(other)
                .unwrap_or_default()
                .trim()
                .to_string(),
        };
        let name = if prefix.is_empty() {
            k
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            Value::Mapping(inner) => flatten(inner, &name, out),
            v => out(name, v.clone()),
        }
    }
}

static REMAPS: OnceLock<Vec<Remap>> = OnceLock::new();

/// Installs the process's remaps (once, before any node starts).
pub fn install_remaps(remaps: Vec<Remap>) {
    let _ = REMAPS.set(remaps);
}

/// The name `resolved` (absolute) of node `node` (namespace `ns`) after the remaps: a rule
/// matches when its `FROM`, resolved the same way, equals `resolved`; the first match wins.
pub fn remap(node: &str, ns: &str, resolved: &str) -> String {
    let Some(rules) = REMAPS.get() else {
        return resolved.to_string();
    };
    let ns = ns.trim_end_matches('/');
    let absolute = |n: &str| -> String {
        if let Some(rest) = n.strip_prefix("~/") {
            format!("{ns}/{node}/{rest}")
        } else if n.starts_with('/') {
            n.to_string()
        } else {
            format!("{ns}/{n}")
        }
    };
    for r in rules {
        if r.node.as_deref().is_some_and(|n| n != node) {
            continue;
        }
        if absolute(&r.from) == resolved {
            return absolute(&r.to);
        }
    }
    resolved.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Result<RosArgs, String> {
        RosArgs::parse(&s.split_whitespace().map(String::from).collect::<Vec<_>>())
    }

    #[test]
    fn params_remaps_and_node_renames() {
        let a = args("-p cycle_period:=0.002 -p axis_node:axes.x.max_velocity:=500 -r __node:=arm -r ~/axis_states:=/arm/states").unwrap();
        assert_eq!(
            a.params,
            [
                (None, "name".to_string(), Value::String("arm".into())),
                (None, "cycle_period".to_string(), Value::from(0.002)),
                (
                    Some("axis_node".to_string()),
                    "axes.x.max_velocity".to_string(),
                    Value::from(500)
                ),
            ]
        );
        assert_eq!(a.remaps[0].from, "~/axis_states");
        let mut entry: Mapping =
            serde_yaml::from_str("kind: axis_node\naxes: {x: {jerk: 1.0}}").unwrap();
        a.apply_params(&mut entry, "axis_node");
        // The rename applies first (it comes from -r); the node-scoped override then no
        // longer matches the renamed node, as in ROS.
        assert_eq!(entry["name"], Value::String("arm".into()));
        assert_eq!(entry["cycle_period"], Value::from(0.002));
        assert_eq!(entry["axes"]["x"]["jerk"], Value::from(1.0));
        assert!(entry["axes"]["x"].get("max_velocity").is_none());
    }

    #[test]
    fn unknown_and_malformed_arguments_are_refused() {
        assert!(args("--enclave /x")
            .unwrap_err()
            .contains("unsupported argument '--enclave'"));
        assert!(args("-p cycle_period").unwrap_err().contains(":="));
        assert!(args("-p").unwrap_err().contains("needs an argument"));
        assert!(args("-p x:=[1, 2").unwrap_err().contains("not YAML"));
    }

    #[test]
    fn params_files_in_ros_form() {
        let dir = std::env::temp_dir().join(format!("ros_args_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("p.yaml");
        std::fs::write(
            &f,
            "/**:\n  ros__parameters: {state_rate: 25.0}\n/axis_node:\n  ros__parameters:\n    axes:\n      x: {max_velocity: 300.0}\n",
        )
        .unwrap();
        let a = args(&format!(
            "--params-file {} -p state_rate:=10.0",
            f.display()
        ))
        .unwrap();
        let mut entry: Mapping = serde_yaml::from_str("kind: axis_node\naxes: {x: {}}").unwrap();
        a.apply_params(&mut entry, "axis_node");
        assert_eq!(entry["state_rate"], Value::from(10.0)); // -p after the file wins
        assert_eq!(entry["axes"]["x"]["max_velocity"], Value::from(300.0));
        let mut other: Mapping = serde_yaml::from_str("kind: planar_node").unwrap();
        a.apply_params(&mut other, "planar_node");
        assert!(other.get("axes").is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
