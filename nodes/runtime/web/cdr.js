// ROS 2 messages in the browser: parses a `ros2msg` definition (the main type, then each
// dependency after a line of '=' and "MSG: pkg/Name", as rosbag2 and the live feed write it)
// and decodes CDR (little or big endian, with the 4-byte encapsulation header) into plain
// objects. Only what ROS 2 messages use: primitives, strings, fixed and bounded arrays,
// sequences and nested messages. Constants are skipped.
"use strict";

const PRIMITIVES = {
  bool: [1, "u8"], byte: [1, "u8"], char: [1, "u8"], uint8: [1, "u8"], int8: [1, "i8"],
  uint16: [2, "u16"], int16: [2, "i16"], uint32: [4, "u32"], int32: [4, "i32"],
  uint64: [8, "u64"], int64: [8, "i64"], float32: [4, "f32"], float64: [8, "f64"],
};

// builtin_interfaces are not always listed among the dependencies.
const BUILTIN = {
  "builtin_interfaces/Time": [{ type: "int32", name: "sec", array: null }, { type: "uint32", name: "nanosec", array: null }],
  "builtin_interfaces/Duration": [{ type: "int32", name: "sec", array: null }, { type: "uint32", name: "nanosec", array: null }],
};

function parseFields(text) {
  const fields = [];
  for (let line of text.split("\n")) {
    line = line.replace(/#.*$/, "").trim();
    if (!line) continue;
    const m = line.match(/^(\S+)\s+(\S+)(\s+.*)?$/);
    if (!m) continue;
    if (m[2].includes("=")) continue; // constant NAME=value
    if (m[3] && m[3].trim().startsWith("=")) continue; // constant NAME = value
    let type = m[1].replace(/<=\d+$/, ""); // bounded string
    let array = null; // null | -1 (sequence) | n (fixed)
    const a = type.match(/^(.*)\[(<=)?(\d*)\]$/);
    if (a) {
      type = a[1].replace(/<=\d+$/, "");
      array = a[3] === "" || a[2] ? -1 : Number(a[3]);
    }
    fields.push({ type, name: m[2], array });
  }
  return fields;
}

// Parses a full definition: {root: "pkg/msg/Name", types: {"pkg/Name": fields}}.
function parseDefinition(rootName, text) {
  const types = {};
  const parts = text.split(/\n=+\n/);
  const pkg = rootName.split("/")[0];
  types[short(rootName)] = { pkg, fields: parseFields(parts[0]) };
  for (const part of parts.slice(1)) {
    const m = part.match(/^\s*MSG:\s*(\S+)\s*\n([\s\S]*)$/);
    if (m) types[short(m[1])] = { pkg: m[1].split("/")[0], fields: parseFields(m[2]) };
  }
  return { root: short(rootName), types };
}

// "pkg/msg/Name" and "pkg/Name" -> "pkg/Name".
function short(name) {
  const p = name.split("/");
  return p.length === 3 ? p[0] + "/" + p[2] : name;
}

class Reader {
  constructor(bytes) {
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.little = (bytes[1] & 1) === 1; // CDR_LE = 0x0001, CDR_BE = 0x0000
    this.base = 4; // alignment counts from the end of the encapsulation header
    this.pos = 4;
  }
  align(n) {
    const off = (this.pos - this.base) % n;
    if (off) this.pos += n - off;
  }
  prim(kind, size) {
    this.align(size);
    const v = this.view, p = this.pos, l = this.little;
    this.pos += size;
    switch (kind) {
      case "u8": return v.getUint8(p);
      case "i8": return v.getInt8(p);
      case "u16": return v.getUint16(p, l);
      case "i16": return v.getInt16(p, l);
      case "u32": return v.getUint32(p, l);
      case "i32": return v.getInt32(p, l);
      case "u64": return Number(v.getBigUint64(p, l));
      case "i64": return Number(v.getBigInt64(p, l));
      case "f32": return v.getFloat32(p, l);
      case "f64": return v.getFloat64(p, l);
    }
    throw new Error("unknown primitive " + kind);
  }
  string() {
    const n = this.prim("u32", 4);
    const bytes = new Uint8Array(this.view.buffer, this.view.byteOffset + this.pos, Math.max(0, n - 1));
    this.pos += n;
    return new TextDecoder().decode(bytes);
  }
}

function resolve(def, type, pkg) {
  if (BUILTIN[type]) return { fields: BUILTIN[type], pkg: "builtin_interfaces" };
  const key = type.includes("/") ? short(type) : pkg + "/" + type;
  if (def.types[key]) return def.types[key];
  if (BUILTIN[key]) return { fields: BUILTIN[key], pkg: "builtin_interfaces" };
  // Header and friends may be named without their package.
  const hit = Object.keys(def.types).find((k) => k.endsWith("/" + type));
  if (hit) return def.types[hit];
  throw new Error("type not in the definition: " + type);
}

function readValue(r, def, type, pkg) {
  const p = PRIMITIVES[type];
  if (p) {
    const v = r.prim(p[1], p[0]);
    return type === "bool" ? v !== 0 : v;
  }
  if (type === "string" || type === "wstring") return r.string();
  const t = resolve(def, type, pkg);
  return readStruct(r, def, t);
}

function readStruct(r, def, t) {
  const out = {};
  for (const f of t.fields) {
    if (f.array == null) {
      out[f.name] = readValue(r, def, f.type, t.pkg);
    } else {
      const n = f.array >= 0 ? f.array : r.prim("u32", 4);
      const arr = new Array(n);
      for (let i = 0; i < n; i++) arr[i] = readValue(r, def, f.type, t.pkg);
      out[f.name] = arr;
    }
  }
  return out;
}

// A decoder for one channel: bytes (Uint8Array with the encapsulation header) -> object.
function makeDecoder(schemaName, definition) {
  const def = parseDefinition(schemaName, definition);
  const root = def.types[def.root];
  return (bytes) => readStruct(new Reader(bytes), def, root);
}

if (typeof module !== "undefined") module.exports = { makeDecoder, parseDefinition };
