#!/usr/bin/env python3
"""Python cyclonedds types for the motion_msgs interfaces (for a Python test peer over DDS).

Reads the same interface files as msgs/build.rs (msg/, srv/, action/ and ros_deps/<pkg>/...)
and generates `cyclonedds.idl.IdlStruct` dataclasses with the DDS type names rmw uses, e.g.
`motion_msgs::msg::dds_::AxisState_`, `motion_msgs::srv::dds_::MoveAbsolute_Request_`,
`motion_msgs::action::dds_::MoveAbsolute_Goal_`, plus the action wrapper types rmw puts on the
wire (`..._SendGoal_Request_` = goal_id + goal, `..._SendGoal_Response_` = accepted + stamp,
`..._GetResult_Request_` = goal_id, `..._GetResult_Response_` = status + result,
`..._FeedbackMessage_` = goal_id + feedback).

Library use (any python3 with the `cyclonedds` package):

    sys.path.insert(0, 'msgs/tools'); import gen_python_types
    types = gen_python_types.load_types('msgs')            # {ROS name: class}
    AxisState = types['motion_msgs/msg/AxisState']
    data = AxisState(name='x').serialize()                  # XCDR1 bytes with the 4-byte header
    Goal = types['motion_msgs/action/MoveAbsolute_SendGoal_Request']

Command line: `python3 gen_python_types.py [MSGS_DIR] [-o motion_msgs_types.py]` writes (or
prints) the module source; the module has the classes (named `pkg__kind__Name`) and `TYPES`.

Field types: bool -> bool, byte/char/uint8 -> types.uint8, intN/uintN/floatN -> types.*,
string -> str (string<=N -> types.bounded_str[N]), wstring -> types.sequence[types.uint16]
(UTF-16 code units, as ros2-client sends them), T[N] -> types.array[T, N], T[<=N] ->
types.sequence[T, N], T[] -> types.sequence[T], time/duration -> builtin_interfaces Time/Duration.
Every field has its IDL default (or zero), so `Type()` is a valid message.

Service calls over rmw_cyclonedds carry a request header before the payload; that framing is
the peer's business, these are the plain ROS types.

The parser is rosidl_adapter's (imported, or loaded from Debian's python3-rosidl at
/usr/lib/python3/dist-packages); without it a small built-in parser handles the common syntax.
"""

import importlib.util
import keyword
import os
import re
import sys

OWN_PACKAGE = 'motion_msgs'
_ROSIDL_PARSER_PATHS = [
    '/usr/lib/python3/dist-packages/rosidl_adapter/parser.py',
    '/opt/ros/jazzy/lib/python3.12/site-packages/rosidl_adapter/parser.py',
]


# --------------------------------------------------------------------------------------------
# Parsing
# --------------------------------------------------------------------------------------------

def _load_rosidl_parser():
    try:
        from rosidl_adapter import parser  # noqa: F401
        return parser
    except ImportError:
        pass
    for path in _ROSIDL_PARSER_PATHS:
        if os.path.exists(path):
            try:
                spec = importlib.util.spec_from_file_location('_rosidl_adapter_parser', path)
                mod = importlib.util.module_from_spec(spec)
                spec.loader.exec_module(mod)
                return mod
            except Exception:  # pragma: no cover - unusual installations
                continue
    return None


class _Type:
    """The attributes of rosidl_adapter.parser.Type that the generator uses."""

    def __init__(self, s, context_pkg):
        self.is_array = s.endswith(']')
        self.array_size = None
        self.is_upper_bound = False
        if self.is_array:
            i = s.rindex('[')
            size = s[i + 1:-1]
            if size:
                self.is_upper_bound = size.startswith('<=')
                self.array_size = int(size[2:] if self.is_upper_bound else size)
            s = s[:i]
        self.string_upper_bound = None
        m = re.match(r'^(w?string)<=(\d+)$', s)
        if s in _PRIMITIVES:
            self.pkg_name, self.type = None, s
        elif m:
            self.pkg_name, self.type = None, m.group(1)
            self.string_upper_bound = int(m.group(2))
        elif '/' in s:
            self.pkg_name, self.type = s.split('/')
        else:
            self.pkg_name, self.type = context_pkg, s

    def is_primitive_type(self):
        return self.pkg_name is None


_PRIMITIVES = ['bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16',
               'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring', 'duration', 'time']


def _mini_value(t, s):
    def one(v):
        v = v.strip()
        if t.type == 'bool':
            return v.lower() in ('true', '1')
        if t.type in ('float32', 'float64'):
            return float(v)
        if t.type in ('string', 'wstring'):
            if len(v) >= 2 and v[0] == v[-1] and v[0] in '"\'':
                v = v[1:-1].replace('\\' + v[0], v[0])
            return v
        return int(v, 0) if not v.lstrip('-').isdigit() else int(v)
    if t.is_array:
        inner = s.strip()[1:-1]
        if t.type in ('string', 'wstring'):
            items = re.findall(r'"(?:[^"\\]|\\.)*"|\'(?:[^\'\\]|\\.)*\'|[^,]+', inner)
        else:
            items = [x for x in inner.split(',')] if inner.strip() else []
        return [one(x) for x in items if x.strip()]
    return one(s)


class _Spec:
    def __init__(self, pkg, name, text):
        self.msg_name = name
        self.pkg_name = pkg
        self.fields, self.constants = [], []
        for line in text.replace('\t', ' ').splitlines():
            line = line.split('#', 1)[0].strip()
            if not line:
                continue
            type_string, _, rest = line.partition(' ')
            rest = rest.strip()
            if '=' in rest:
                name_, _, value = rest.partition('=')
                t = _Type(type_string, pkg)
                c = type('C', (), {})()
                c.name, c.type, c.value = name_.strip(), type_string, _mini_value(t, value.strip())
                self.constants.append(c)
            else:
                name_, _, default = rest.partition(' ')
                t = _Type(type_string, pkg)
                f = type('F', (), {})()
                f.name, f.type = name_, t
                f.default_value = _mini_value(t, default.strip()) if default.strip() else None
                self.fields.append(f)


def _split_parts(text, n):
    lines = text.splitlines()
    idx = [i for i, line in enumerate(lines) if line == '---']
    if len(idx) != n - 1:
        raise ValueError('expected %d "---" separators' % (n - 1))
    bounds = [-1] + idx + [len(lines)]
    return ['\n'.join(lines[bounds[i] + 1:bounds[i + 1]]) for i in range(n)]


def _parse(parser, pkg, kind, path):
    """[(suffix, spec)] for one file; suffix '' for messages."""
    name = os.path.splitext(os.path.basename(path))[0]
    if parser is not None:
        if kind == 'msg':
            return [('', parser.parse_message_file(pkg, path))]
        if kind == 'srv':
            s = parser.parse_service_file(pkg, path)
            return [('_Request', s.request), ('_Response', s.response)]
        a = parser.parse_action_file(pkg, path)
        return [('_Goal', a.goal), ('_Result', a.result), ('_Feedback', a.feedback)]
    with open(path, encoding='utf-8') as h:
        text = h.read()
    if kind == 'msg':
        return [('', _Spec(pkg, name, text))]
    suffixes = ['_Request', '_Response'] if kind == 'srv' else ['_Goal', '_Result', '_Feedback']
    parts = _split_parts(text, len(suffixes))
    return [(sfx, _Spec(pkg, name + sfx, p)) for sfx, p in zip(suffixes, parts)]


def _package_dirs(msgs_dir):
    yield OWN_PACKAGE, msgs_dir
    deps = os.path.join(msgs_dir, 'ros_deps')
    if os.path.isdir(deps):
        for pkg in sorted(os.listdir(deps)):
            if os.path.isdir(os.path.join(deps, pkg)):
                yield pkg, os.path.join(deps, pkg)


# --------------------------------------------------------------------------------------------
# Generation
# --------------------------------------------------------------------------------------------

_SCALARS = {
    'bool': 'bool', 'byte': 'types.uint8', 'char': 'types.uint8',
    'int8': 'types.int8', 'uint8': 'types.uint8', 'int16': 'types.int16',
    'uint16': 'types.uint16', 'int32': 'types.int32', 'uint32': 'types.uint32',
    'int64': 'types.int64', 'uint64': 'types.uint64',
    'float32': 'types.float32', 'float64': 'types.float64',
}
_ZERO = {'bool': 'False', 'float32': '0.0', 'float64': '0.0'}


class _Struct:
    def __init__(self, ros_name, dds_name, fields, doc):
        self.ros_name = ros_name      # e.g. motion_msgs/msg/AxisState
        self.dds_name = dds_name      # e.g. motion_msgs::msg::dds_::AxisState_
        self.fields = fields          # [(name, annotation, default_expr, [dependency ros names])]
        self.doc = doc

    @property
    def class_name(self):
        return self.ros_name.replace('/', '__')


def _msg_ref(pkg, name):
    return '%s/msg/%s' % (pkg, name)


def _class(ros_name):
    return ros_name.replace('/', '__')


def _field(f):
    """(annotation, default expression, dependencies) of a parsed field."""
    t = f.type
    deps = []
    if t.is_primitive_type():
        if t.type in ('time', 'duration'):
            ref = _msg_ref('builtin_interfaces', t.type.capitalize())
            deps.append(ref)
            scalar, zero = _class(ref), '%s()' % _class(ref)
        elif t.type == 'string':
            scalar = 'types.bounded_str[%d]' % t.string_upper_bound if t.string_upper_bound \
                else 'str'
            zero = "''"
        elif t.type == 'wstring':
            scalar = 'types.sequence[types.uint16%s]' % (
                ', %d' % t.string_upper_bound if t.string_upper_bound else '')
            zero = '[]'
        else:
            scalar, zero = _SCALARS[t.type], _ZERO.get(t.type, '0')
    else:
        ref = _msg_ref(t.pkg_name, t.type)
        deps.append(ref)
        scalar, zero = _class(ref), '%s()' % _class(ref)

    def lit(v):
        if t.type == 'wstring':
            b = v.encode('utf-16-le')
            return repr([int.from_bytes(b[i:i + 2], 'little') for i in range(0, len(b), 2)])
        return repr(v)

    default = f.default_value
    if not t.is_array:
        return scalar, (lit(default) if default is not None else zero), deps
    if t.array_size and not t.is_upper_bound:
        ann = 'types.array[%s, %d]' % (scalar, t.array_size)
        expr = '[%s for _ in range(%d)]' % (zero, t.array_size)
    elif t.array_size:
        ann = 'types.sequence[%s, %d]' % (scalar, t.array_size)
        expr = '[]'
    else:
        ann = 'types.sequence[%s]' % scalar
        expr = '[]'
    if default is not None:
        expr = '[%s]' % ', '.join(lit(v) for v in default)
    return ann, expr, deps


def _structs(msgs_dir, parser):
    structs = []
    for pkg, root in _package_dirs(msgs_dir):
        for kind in ('msg', 'srv', 'action'):
            d = os.path.join(root, kind)
            if not os.path.isdir(d):
                continue
            for fn in sorted(os.listdir(d)):
                if not fn.endswith('.' + kind):
                    continue
                name = fn[:-len(kind) - 1]
                for suffix, spec in _parse(parser, pkg, kind, os.path.join(d, fn)):
                    fields = []
                    for f in spec.fields:
                        ann, expr, deps = _field(f)
                        fields.append((f.name, ann, expr, deps))
                    structs.append(_Struct(
                        '%s/%s/%s%s' % (pkg, kind, name, suffix),
                        '%s::%s::dds_::%s%s_' % (pkg, kind, name, suffix),
                        fields, 'ROS 2 %s/%s/%s%s' % (pkg, kind, name, suffix)))
                if kind == 'action':
                    structs.extend(_action_wrappers(pkg, name))
    return structs


def _action_wrappers(pkg, name):
    """The types rmw builds around goal / result / feedback (rosidl action wrappers)."""
    base = '%s/action/%s' % (pkg, name)
    uuid = _msg_ref('unique_identifier_msgs', 'UUID')
    time = _msg_ref('builtin_interfaces', 'Time')

    def nested(field_name, ref):
        return (field_name, _class(ref), '%s()' % _class(ref), [ref])

    def mk(suffix, fields):
        return _Struct(base + suffix, '%s::action::dds_::%s%s_' % (pkg, name, suffix), fields,
                       'Action wrapper %s%s' % (base, suffix))
    return [
        mk('_SendGoal_Request', [nested('goal_id', uuid), nested('goal', base + '_Goal')]),
        mk('_SendGoal_Response', [('accepted', 'bool', 'False', []), nested('stamp', time)]),
        mk('_GetResult_Request', [nested('goal_id', uuid)]),
        mk('_GetResult_Response', [('status', 'types.int8', '0', []),
                                   nested('result', base + '_Result')]),
        mk('_FeedbackMessage', [nested('goal_id', uuid), nested('feedback', base + '_Feedback')]),
    ]


def _ordered(structs):
    """Dependencies first (annotations are evaluated when a class is created)."""
    by_name = {s.ros_name: s for s in structs}
    done, out = set(), []

    def visit(s, stack):
        if s.ros_name in done:
            return
        if s.ros_name in stack:
            raise ValueError('recursive type %s' % s.ros_name)
        for f in s.fields:
            for dep in f[3]:
                if dep not in by_name:
                    raise ValueError('%s: unknown type %s (vendor it under ros_deps/)' %
                                     (s.ros_name, dep))
                visit(by_name[dep], stack | {s.ros_name})
        done.add(s.ros_name)
        out.append(s)
    for s in structs:
        visit(s, frozenset())
    return out


def generate_source(msgs_dir):
    """Python source of a module defining every type and `TYPES` ({ROS name: class})."""
    parser = _load_rosidl_parser()
    out = [
        '# Generated by msgs/tools/gen_python_types.py from the motion_msgs interface files.',
        'from dataclasses import dataclass, field',
        'from cyclonedds.idl import IdlStruct',
        'from cyclonedds.idl import types',
        '',
    ]
    ordered = _ordered(_structs(msgs_dir, parser))
    for s in ordered:
        out.append('')
        out.append('@dataclass')
        out.append('class %s(IdlStruct, typename=%r):' % (s.class_name, s.dds_name))
        out.append('    """%s"""' % s.doc)
        for name, ann, expr, _ in s.fields:
            attr = name + '_' if keyword.iskeyword(name) else name
            out.append('    %s: %s = field(default_factory=lambda: %s)' % (attr, ann, expr))
        if not s.fields:
            # rosidl gives empty structures one uint8 member (one byte on the wire).
            out.append('    structure_needs_at_least_one_member: types.uint8 = 0')
        out.append('')
    out.append('')
    out.append('TYPES = {')
    for s in ordered:
        out.append('    %r: %s,' % (s.ros_name, s.class_name))
    out.append('}')
    return '\n'.join(out) + '\n'


def load_types(msgs_dir=None):
    """Generates the types in memory and returns {ROS name: class}, e.g.
    types['motion_msgs/msg/AxisState'], types['motion_msgs/srv/Power_Request'],
    types['motion_msgs/action/MoveAbsolute_SendGoal_Request']."""
    if msgs_dir is None:
        msgs_dir = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    namespace = {'__name__': 'motion_msgs_types'}
    exec(compile(generate_source(msgs_dir), '<motion_msgs_types>', 'exec'), namespace)
    return dict(namespace['TYPES'])


def main(argv):
    args = list(argv)
    out_path = None
    if '-o' in args:
        i = args.index('-o')
        out_path = args[i + 1]
        del args[i:i + 2]
    msgs_dir = args[0] if args else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    src = generate_source(msgs_dir)
    if out_path:
        with open(out_path, 'w', encoding='utf-8') as h:
            h.write(src)
    else:
        sys.stdout.write(src)


if __name__ == '__main__':
    main(sys.argv[1:])
