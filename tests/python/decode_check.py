#!/usr/bin/env python3
"""decode_check.py DIR TYPE...: the Python classes of package comlearn (lcm-gen --python) decode
what the C bindings encode. As tests/java/DecodeCheck.java: for each TYPE, DIR/TYPE.bin is the C
encoding of check_messages' fixture and DIR/TYPE.txt its fields as C sees them, one
"name[i][j]=value" line per element (integers in decimal, booleans 0/1, floating point as the hex
of its IEEE bits, strings as '"' and the hex of their UTF-8 bytes). The class is found by the
buffer's fingerprint, the object decoded, listed in the same format and compared line by line,
re-encoded and compared byte for byte; every other type's class must refuse the buffer.
Exit status 0 only if every check of every type passed."""

import struct
import sys

import comlearn


def classes():
    return {name: getattr(comlearn, name) for name in dir(comlearn)
            if name.endswith("_t") and hasattr(getattr(comlearn, name), "_get_packed_fingerprint")}


def dump_value(v):
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "0x" + struct.pack(">d", v).hex()
    if isinstance(v, str):
        return '"' + v.encode("utf-8").hex()
    raise TypeError("unexpected field type %s" % type(v))


def dump(name, v, out):
    if isinstance(v, (list, tuple)):
        for i, e in enumerate(v):
            dump("%s[%d]" % (name, i), e, out)
    else:
        out.append("%s=%s" % (name, dump_value(v)))


def listing(obj):
    out = []
    for f in obj.__slots__:
        dump(f, getattr(obj, f), out)
    return out


def main(argv):
    if len(argv) < 3:
        print("usage: decode_check.py DIR TYPE...", file=sys.stderr)
        return 2
    d, types = argv[1], argv[2:]
    cls = classes()
    failures = 0

    def fail(t, what):
        nonlocal failures
        failures += 1
        print("FAIL %s: %s" % (t, what))

    if sorted(cls) != sorted(types):
        fail("package", "classes %s, types built %s" % (sorted(cls), sorted(types)))
    for t in types:
        with open("%s/%s.bin" % (d, t), "rb") as f:
            buf = f.read()
        with open("%s/%s.txt" % (d, t), encoding="ascii") as f:
            want = f.read().splitlines()
        by_fp = [c for c in cls.values() if buf[:8] == c._get_packed_fingerprint()]
        if len(by_fp) != 1 or by_fp[0] is not cls.get(t):
            fail(t, "fingerprint names %s" % [c.__name__ for c in by_fp])
            continue
        obj = cls[t].decode(buf)
        got = listing(obj)
        if got != want:
            for k in range(max(len(got), len(want))):
                g = got[k] if k < len(got) else "(none)"
                w = want[k] if k < len(want) else "(none)"
                if g != w:
                    fail(t, "line %d: python %s, C %s" % (k + 1, g, w))
                    break
        if obj.encode() != buf:
            fail(t, "re-encoding differs from the C bytes")
        for other, c in cls.items():
            if other == t:
                continue
            try:
                c.decode(buf)
                fail(t, "%s decoded its buffer" % other)
            except ValueError:
                pass
        if failures == 0:
            print("ok %s: %d fields, %d bytes" % (t, len(got), len(buf)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
