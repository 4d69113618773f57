#!/usr/bin/python3
"""Checks that an exported scene names a file exactly, whatever its name holds (quotes,
backslashes, newlines, XML specials, bytes that are not UTF-8), for hostile_suite.sh.

usage: hostile_names.py check-pbrt|check-mitsuba DIR NAME
  Passes when DIR does not exist (the export was refused). Otherwise DIR must hold the .pbrt
  (or .xml) files, and one string of them, read back as the renderer reads it, must be NAME or a
  path ending in /NAME. pbrt: strings are "..." with backslash escapes (pbrt-v4's tokenizer:
  \\n \\t \\" \\\\ ...), and hold no raw newline. Mitsuba: XML parsed as a document (the
  expat parser; attribute values unescaped), which refuses text that is not UTF-8.
"""
import os
import sys
import xml.etree.ElementTree as ET

mode, folder, name = sys.argv[1], sys.argv[2], os.fsencode(sys.argv[3])
if not os.path.isdir(folder):
    sys.exit(0)


def names_match(value):
    return value == name or value.endswith(b"/" + name)


def pbrt_strings(text):
    """The quoted strings of a pbrt file, unescaped as pbrt-v4's tokenizer does."""
    out, i = [], 0
    escapes = {ord("n"): b"\n", ord("t"): b"\t", ord("r"): b"\r", ord("b"): b"\b",
               ord("f"): b"\f", ord("\\"): b"\\", ord("'"): b"'", ord('"'): b'"'}
    while i < len(text):
        c = text[i]
        if c == ord("#"):  # comment to the end of the line
            while i < len(text) and text[i] != ord("\n"):
                i += 1
        elif c == ord('"'):
            i += 1
            s = b""
            while True:
                if i >= len(text):
                    raise SystemExit("unterminated string")
                c = text[i]
                if c == ord("\n"):
                    raise SystemExit("raw newline inside a pbrt string")
                if c == ord('"'):
                    break
                if c == ord("\\"):
                    i += 1
                    if text[i] not in escapes:
                        raise SystemExit("unknown escape \\%c" % text[i])
                    s += escapes[text[i]]
                else:
                    s += bytes([c])
                i += 1
            out.append(s)
        i += 1
    return out


found = []
for f in sorted(os.listdir(folder)):
    path = os.path.join(folder, f)
    if mode == "check-pbrt" and f.endswith(".pbrt"):
        found += pbrt_strings(open(path, "rb").read())
    elif mode == "check-mitsuba" and f.endswith(".xml"):
        try:
            root = ET.fromstring(open(path, "rb").read())
        except ET.ParseError as e:
            raise SystemExit(f"{f}: not well-formed XML: {e}")
        for el in root.iter():
            found += [os.fsencode(v) for v in el.attrib.values()]
if not any(names_match(s) for s in found):
    raise SystemExit(f"no string names {name!r}; strings: {found[:12]!r}")
