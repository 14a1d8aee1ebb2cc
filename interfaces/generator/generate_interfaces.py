#!/usr/bin/env python3
"""Generates mcvio's interface code from the ROS 2 .msg files in interfaces/msg.

For every msg/<pkg>/<Name>.msg it writes
  idl/<pkg>/msg/<Name>.idl           module pkg::msg::dds_ { struct Name_ }, as rmw_fastrtps names types
  cpp/<pkg>/msg/<Name>*.{h,cxx}      fastddsgen's C++ (CDR serialisation, TopicDataType)
and once
  cpp/mcvio/interfaces/message_registry_data.inc   .msg text, rosbag2-style full definition and
                                                     RIHS01 type hash of every type
  cpp/mcvio/interfaces/ros_type_traits.hpp          RosType<T> traits tying C++ types to ROS names

The .msg files are the single source of truth: the IDL, the definitions embedded in bags and the type
hashes announced on the wire all derive from them, so they cannot disagree.
"""
import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

PRIMITIVES = {
    # msg type: (IDL type, RIHS01 field type id)
    'bool': ('boolean', 15), 'byte': ('octet', 16), 'char': ('uint8', 3),
    'int8': ('int8', 2), 'uint8': ('uint8', 3), 'int16': ('int16', 4), 'uint16': ('uint16', 5),
    'int32': ('int32', 6), 'uint32': ('uint32', 7), 'int64': ('int64', 8), 'uint64': ('uint64', 9),
    'float32': ('float', 10), 'float64': ('double', 11),
    'string': ('string', 17), 'wstring': ('wstring', 18),
}
NESTED_ID = 1
BOUNDED_STRING_ID = 21
BOUNDED_WSTRING_ID = 22
ARRAY_OFFSET, BOUNDED_SEQ_OFFSET, UNBOUNDED_SEQ_OFFSET = 48, 96, 144

FIELD_RE = re.compile(r'^([\w/]+)(<=\d+)?(\[(<=)?(\d*)\])?\s+(\w+)(\s+.*)?$')
CONST_RE = re.compile(r'^([\w/]+)\s+([A-Z][A-Z0-9_]*)\s*=\s*(.*)$')


class MsgError(Exception):
    pass


class Field:
    def __init__(self, base, string_bound, array_kind, array_size, name):
        self.base = base                  # primitive name or 'pkg/msg/Name'
        self.string_bound = string_bound  # int or 0
        self.array_kind = array_kind      # None, 'array', 'bounded', 'unbounded'
        self.array_size = array_size      # int or 0
        self.name = name

    @property
    def nested(self):
        return self.base not in PRIMITIVES


class Message:
    def __init__(self, pkg, name, text, fields, constants):
        self.pkg, self.name, self.text = pkg, name, text
        self.fields, self.constants = fields, constants

    @property
    def full_name(self):
        return f'{self.pkg}/msg/{self.name}'


def parse_msg(pkg, name, text, path):
    fields, constants = [], []
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.split('#', 1)[0].strip()
        if not line:
            continue
        m = CONST_RE.match(line)
        if m:
            constants.append((m.group(1), m.group(2), m.group(3).strip()))
            continue
        m = FIELD_RE.match(line)
        if not m:
            raise MsgError(f'{path}:{lineno}: cannot parse "{raw.strip()}"')
        base, sbound, arr, bounded, size, fname = m.group(1, 2, 3, 4, 5, 6)
        if base not in PRIMITIVES:
            parts = base.split('/')
            if len(parts) == 1:
                base = f'{pkg}/msg/{parts[0]}'
            elif len(parts) == 2:
                base = f'{parts[0]}/msg/{parts[1]}'
            elif not (len(parts) == 3 and parts[1] == 'msg'):
                raise MsgError(f'{path}:{lineno}: bad type name "{m.group(1)}"')
        if sbound and base not in ('string', 'wstring'):
            raise MsgError(f'{path}:{lineno}: only strings take a <=N bound')
        kind, n = None, 0
        if arr:
            if bounded:
                kind, n = 'bounded', int(size)
            elif size:
                kind, n = 'array', int(size)
            else:
                kind = 'unbounded'
        fields.append(Field(base, int(sbound[2:]) if sbound else 0, kind, n, fname))
    return Message(pkg, name, text, fields, constants)


def load_messages(msg_root):
    msgs = {}
    for pkg in sorted(os.listdir(msg_root)):
        pdir = os.path.join(msg_root, pkg)
        if not os.path.isdir(pdir):
            continue
        for fn in sorted(os.listdir(pdir)):
            if fn.endswith('.msg'):
                path = os.path.join(pdir, fn)
                with open(path, encoding='utf-8') as f:
                    m = parse_msg(pkg, fn[:-4], f.read(), path)
                msgs[m.full_name] = m
    for m in msgs.values():
        for f in m.fields:
            if f.nested and f.base not in msgs:
                raise MsgError(f'{m.full_name}: field {f.name} uses unknown type {f.base}')
    return msgs


# ---- IDL -------------------------------------------------------------------------------------

def idl_type(f):
    if f.nested:
        pkg, _, name = f.base.split('/')
        return f'{pkg}::msg::dds_::{name}_'
    t = PRIMITIVES[f.base][0]
    if f.string_bound:
        t = f'{t}<{f.string_bound}>'
    return t


def write_idl(m, out_dir):
    includes = sorted({f.base for f in m.fields if f.nested})
    guard = f'MCVIO_{m.pkg.upper()}_MSG_{m.name.upper()}_IDL'
    lines = [f'// Generated from {m.pkg}/msg/{m.name}.msg by generate_interfaces.py.',
             f'#ifndef {guard}', f'#define {guard}']
    lines += [f'#include "{inc.split("/")[0]}/msg/{inc.split("/")[2]}.idl"' for inc in includes]
    lines += [f'module {m.pkg} {{', '  module msg {']
    if m.constants:
        lines.append(f'    module {m.name}_Constants {{')
        for ctype, cname, cval in m.constants:
            t = PRIMITIVES[ctype][0]
            if ctype in ('string', 'wstring'):
                cval = json.dumps(cval.strip('"\''))
            elif ctype == 'bool':
                cval = 'TRUE' if cval.lower() in ('true', '1') else 'FALSE'
            lines.append(f'      const {t} {cname} = {cval};')
        lines.append('    };')
    lines += ['    module dds_ {', f'      struct {m.name}_ {{']
    for f in m.fields:
        t = idl_type(f)
        if f.array_kind == 'array':
            lines.append(f'        {t} {f.name}[{f.array_size}];')
        elif f.array_kind == 'bounded':
            lines.append(f'        sequence<{t}, {f.array_size}> {f.name};')
        elif f.array_kind == 'unbounded':
            lines.append(f'        sequence<{t}> {f.name};')
        else:
            lines.append(f'        {t} {f.name};')
    lines += ['      };', '    };', '  };', '};', f'#endif  // {guard}', '']
    path = os.path.join(out_dir, m.pkg, 'msg', f'{m.name}.idl')
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_if_changed(path, '\n'.join(lines))


# ---- RIHS01 type hash (REP-2011) -------------------------------------------------------------

def field_type_id(f):
    if f.nested:
        tid = NESTED_ID
    elif f.string_bound:
        tid = BOUNDED_STRING_ID if f.base == 'string' else BOUNDED_WSTRING_ID
    else:
        tid = PRIMITIVES[f.base][1]
    offset = {None: 0, 'array': ARRAY_OFFSET, 'bounded': BOUNDED_SEQ_OFFSET,
              'unbounded': UNBOUNDED_SEQ_OFFSET}[f.array_kind]
    return tid + offset


def individual_description(m):
    return {
        'type_name': m.full_name,
        'fields': [{
            'name': f.name,
            'type': {
                'type_id': field_type_id(f),
                'capacity': f.array_size if f.array_kind == 'array' else 0,
                'string_capacity': f.string_bound,
                'nested_type_name': f.base if f.nested else '',
            },
        } for f in m.fields],
    }


def referenced_types(m, msgs):
    seen, queue = set(), [f.base for f in m.fields if f.nested]
    while queue:
        t = queue.pop()
        if t not in seen:
            seen.add(t)
            queue.extend(f.base for f in msgs[t].fields if f.nested)
    return sorted(seen)


def type_hash(m, msgs):
    desc = {
        'type_description': individual_description(m),
        'referenced_type_descriptions': [individual_description(msgs[t])
                                         for t in referenced_types(m, msgs)],
    }
    text = json.dumps(desc, ensure_ascii=True, separators=(', ', ': '), sort_keys=False)
    return 'RIHS01_' + hashlib.sha256(text.encode('utf-8')).hexdigest()


# ---- rosbag2-style full definition -----------------------------------------------------------

def full_definition(m, msgs):
    """The .msg text followed by each dependency's, depth first, as rosbag2 embeds it in bags."""
    order, seen = [], set()

    def visit(msg):
        for f in msg.fields:
            if f.nested and f.base not in seen:
                seen.add(f.base)
                order.append(f.base)
                visit(msgs[f.base])
    visit(m)
    parts = [m.text.rstrip('\n')]
    for t in order:
        pkg, _, name = t.split('/')
        parts.append('=' * 80 + f'\nMSG: {pkg}/{name}\n' + msgs[t].text.rstrip('\n'))
    return '\n'.join(parts) + '\n'


# ---- C++ -------------------------------------------------------------------------------------

def cpp_raw(s):
    return 'R"__mcvio__(' + s + ')__mcvio__"'


def write_registry(msgs, out_dir):
    lines = ['// Generated by generate_interfaces.py: {type, .msg text, full definition, RIHS01 hash}.']
    for name in sorted(msgs):
        m = msgs[name]
        lines.append(f'{{"{name}", {cpp_raw(m.text)},\n {cpp_raw(full_definition(m, msgs))},\n'
                     f' "{type_hash(m, msgs)}"}},')
    path = os.path.join(out_dir, 'mcvio', 'interfaces', 'message_registry_data.inc')
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_if_changed(path, '\n'.join(lines) + '\n')


def write_traits(msgs, out_dir):
    lines = ['// Generated by generate_interfaces.py.', '#pragma once', '', '#include <string_view>', '']
    for name in sorted(msgs):
        pkg, _, n = name.split('/')
        lines.append(f'#include "{pkg}/msg/{n}PubSubTypes.h"')
    lines += ['', 'namespace mcvio::interfaces {', '',
              '/// Ties a generated C++ type to its ROS 2 name and TopicDataType.',
              'template <class T> struct RosType;', '']
    for name in sorted(msgs):
        pkg, _, n = name.split('/')
        cls = f'{pkg}::msg::dds_::{n}_'
        lines += [f'template <> struct RosType<{cls}> {{',
                  f'  using PubSubType = {cls}PubSubType;',
                  f'  static constexpr const char* kName = "{name}";',
                  '};']
    lines += ['', '/// A new TopicDataType for a ROS 2 type name, or nullptr when it is not built in.',
              'inline eprosima::fastdds::dds::TopicDataType* newPubSubType(std::string_view ros_name) {']
    for name in sorted(msgs):
        pkg, _, n = name.split('/')
        lines.append(f'  if (ros_name == "{name}") return new {pkg}::msg::dds_::{n}_PubSubType();')
    lines += ['  return nullptr;', '}', '', '}  // namespace mcvio::interfaces', '']
    path = os.path.join(out_dir, 'mcvio', 'interfaces', 'ros_type_traits.hpp')
    write_if_changed(path, '\n'.join(lines))


def write_if_changed(path, content):
    if os.path.exists(path):
        with open(path, encoding='utf-8') as f:
            if f.read() == content:
                return
    with open(path, 'w', encoding='utf-8') as f:
        f.write(content)


def run_fastddsgen(msgs, idl_dir, cpp_dir, fastddsgen):
    """One fastddsgen call per package; it also emits included types, which we drop."""
    by_pkg = {}
    for m in msgs.values():
        by_pkg.setdefault(m.pkg, []).append(m)
    for pkg, pmsgs in sorted(by_pkg.items()):
        with tempfile.TemporaryDirectory() as tmp:
            idls = [f'{pkg}/msg/{m.name}.idl' for m in pmsgs]
            r = subprocess.run([fastddsgen, '-replace', '-cs', '-d', tmp, '-I', '.'] + idls,
                               cwd=idl_dir, capture_output=True, text=True)
            if r.returncode != 0:
                sys.stderr.write(r.stdout + r.stderr)
                raise MsgError(f'fastddsgen failed for package {pkg}')
            dest = os.path.join(cpp_dir, pkg, 'msg')
            os.makedirs(dest, exist_ok=True)
            for m in pmsgs:
                for suffix in ('.h', '.cxx', 'PubSubTypes.h', 'PubSubTypes.cxx'):
                    src = os.path.join(tmp, m.name + suffix)
                    dst = os.path.join(dest, m.name + suffix)
                    with open(src, encoding='utf-8') as f:
                        write_if_changed(dst, f.read())


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument('--msg-dir', required=True)
    ap.add_argument('--out-dir', required=True)
    ap.add_argument('--fastddsgen', default=shutil.which('fastddsgen'))
    ap.add_argument('--list', action='store_true', help='print the type names and exit')
    ap.add_argument('--hash', metavar='TYPE', help='print the RIHS01 hash of TYPE and exit')
    args = ap.parse_args()
    try:
        msgs = load_messages(args.msg_dir)
        if args.list:
            print('\n'.join(sorted(msgs)))
            return 0
        if args.hash:
            print(type_hash(msgs[args.hash], msgs))
            return 0
        idl_dir = os.path.join(args.out_dir, 'idl')
        cpp_dir = os.path.join(args.out_dir, 'cpp')
        for m in msgs.values():
            write_idl(m, idl_dir)
        if not args.fastddsgen:
            raise MsgError('fastddsgen not found (Debian package fastddsgen)')
        run_fastddsgen(msgs, idl_dir, cpp_dir, args.fastddsgen)
        write_registry(msgs, cpp_dir)
        write_traits(msgs, cpp_dir)
    except MsgError as e:
        sys.stderr.write(f'generate_interfaces: {e}\n')
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
