#!/usr/bin/env python3
"""udpm_test.py: comlearn.udpm, the plain-Python LCM transport, against LCM's wire format.

The byte layouts asserted here are those of LCM's lcm_udpm.c (LC02: magic, seqno, channel, NUL,
payload; LC03: magic, seqno, payload size, fragment offset, fragment number, fragment count, and
the channel only in fragment 0). The loopback case publishes and receives through a real
multicast socket (ttl=0) on a port of its own."""

import os
import random
import struct
import sys
import unittest

from comlearn import udpm, yumi_status_t


class ParseUrl(unittest.TestCase):
    def test_default_and_options(self):
        self.assertEqual(udpm.parse_url("udpm://239.255.76.67:7667?ttl=0"),
                         ("239.255.76.67", 7667, 0, None))
        self.assertEqual(udpm.parse_url("udpm://239.1.2.3:20001?ttl=1&recv_buf_size=2097152"),
                         ("239.1.2.3", 20001, 1, 2097152))
        self.assertEqual(udpm.parse_url("udpm://239.1.2.3:20001"), ("239.1.2.3", 20001, 0, None))

    def test_refused(self):
        bad = {
            "udp://239.1.2.3:7667": "udpm:// URLs only",
            "memq://": "udpm:// URLs only",
            "udpm://239.1.2.3": "no ADDRESS:PORT",
            "udpm://not-an-ip:7667": "not IPv4-address:port",
            "udpm://239.1.2.3:port": "not IPv4-address:port",
            "udpm://10.0.0.1:7667": "not a multicast address",
            "udpm://239.1.2.3:0": "out of range",
            "udpm://239.1.2.3:70000": "out of range",
            "udpm://239.1.2.3:7667?ttl=256": "ttl 256 out of range",
            "udpm://239.1.2.3:7667?ttl=x": "is not a number",
            "udpm://239.1.2.3:7667?recv_buf_size=0": "must be positive",
            "udpm://239.1.2.3:7667?tll=1": "unknown option 'tll'",
        }
        for url, why in bad.items():
            with self.assertRaises(ValueError, msg=url) as cm:
                udpm.parse_url(url)
            self.assertIn(why, str(cm.exception), url)


class Datagrams(unittest.TestCase):
    def test_short_bytes(self):
        d = udpm.encode_datagrams("YUMI_STATUS", b"\x01\x02\x03", 0x01020304)
        self.assertEqual(d, [b"LC02\x01\x02\x03\x04YUMI_STATUS\x00\x01\x02\x03"])
        # the sequence number wraps at 32 bits
        d = udpm.encode_datagrams("A", b"", (1 << 32) + 5)
        self.assertEqual(d, [b"LC02\x00\x00\x00\x05A\x00"])

    def test_short_limit(self):
        channel = "C" * 10
        fits = b"x" * (udpm.SHORT_MAX - len(channel) - 1)
        self.assertEqual(len(udpm.encode_datagrams(channel, fits, 1)), 1)
        self.assertEqual(len(udpm.encode_datagrams(channel, fits + b"x", 1)), 2)

    def test_bad_channel(self):
        for channel in ("", "A" * (udpm.CHANNEL_MAX + 1), "A\0B"):
            with self.assertRaises(ValueError, msg=repr(channel)):
                udpm.encode_datagrams(channel, b"", 0)

    def test_fragment_layout(self):
        payload = bytes(random.Random(1).getrandbits(8) for _ in range(150_000))
        d = udpm.encode_datagrams("BIG", payload, 7)
        self.assertEqual(len(d), 3)  # 150 004 bytes at 65 487 per fragment
        offset = 0
        for k, frag in enumerate(d):
            magic, seqno, size, off, number, count = struct.unpack_from(">IIIIHH", frag)
            self.assertEqual((magic, seqno, size, off, number, count),
                             (udpm.MAGIC_LONG, 7, len(payload), offset, k, 3))
            body = frag[20:]
            if k == 0:
                self.assertTrue(body.startswith(b"BIG\0"))
                body = body[4:]
            self.assertLessEqual(len(frag) - 20, udpm.FRAGMENT_MAX)
            self.assertEqual(body, payload[offset : offset + len(body)])
            offset += len(body)
        self.assertEqual(offset, len(payload))


class Reassembly(unittest.TestCase):
    def setUp(self):
        self.payload = os.urandom(200_000)
        self.frags = udpm.encode_datagrams("BIG", self.payload, 42)
        self.assertEqual(len(self.frags), 4)

    def test_short(self):
        r = udpm.Reassembler()
        self.assertEqual(r.feed(udpm.encode_datagrams("S", b"abc", 1)[0]), ("S", b"abc"))

    def test_in_and_out_of_order(self):
        for order in ([0, 1, 2, 3], [3, 1, 0, 2], [2, 3, 1, 0]):
            r = udpm.Reassembler()
            got = [r.feed(self.frags[k], "h") for k in order]
            self.assertEqual(got[:-1], [None] * 3, order)
            self.assertEqual(got[-1], ("BIG", self.payload), order)
            self.assertEqual(r.discarded, 0)

    def test_repeated_fragment_does_not_complete(self):
        r = udpm.Reassembler()
        for k in (0, 1, 1, 2):
            self.assertIsNone(r.feed(self.frags[k], "h"))
        self.assertEqual(r.discarded, 1)
        self.assertEqual(r.feed(self.frags[3], "h"), ("BIG", self.payload))

    def test_stale_seqno_replaced(self):
        # a half-received message, then a different-sized one under the same seqno and sender
        r = udpm.Reassembler()
        self.assertIsNone(r.feed(self.frags[0], "h"))
        other = os.urandom(140_000)
        newer = udpm.encode_datagrams("BIG", other, 42)
        got = [r.feed(f, "h") for f in newer]
        self.assertEqual(got[-1], ("BIG", other))

    def test_senders_kept_apart(self):
        r = udpm.Reassembler()
        for k in range(3):
            self.assertIsNone(r.feed(self.frags[k], "a"))
        self.assertIsNone(r.feed(self.frags[3], "b"))  # b's fragment 3 does not finish a's
        self.assertEqual(r.feed(self.frags[3], "a"), ("BIG", self.payload))

    def test_garbage_discarded(self):
        r = udpm.Reassembler()
        for junk in (b"", b"LC02", b"XXXX\0\0\0\0abc\0", b"LC02\0\0\0\0\0payload",
                     b"LC02\0\0\0\0" + b"A" * 80 + b"\0", b"LC03\0\0\0\0short",
                     struct.pack(">IIIIHH", udpm.MAGIC_LONG, 1, 10, 0, 2, 2) + b"x",
                     struct.pack(">IIIIHH", udpm.MAGIC_LONG, 1, 4, 0, 0, 1) + b"CH\0toolong"):
            self.assertIsNone(r.feed(junk, "h"), junk)
        self.assertEqual(r.discarded, 8)


class Loopback(unittest.TestCase):
    def test_publish_subscribe(self):
        port = random.Random(os.getpid()).randrange(20000, 60000)
        url = "udpm://239.255.76.67:%d?ttl=0" % port
        lc = udpm.LCM(url)
        try:
            got = []
            sub = lc.subscribe("COMLEARN_PY_.*", lambda ch, data: got.append((ch, data)))
            lc.subscribe("OTHER", lambda ch, data: got.append(("wrong", data)))
            msg = yumi_status_t()
            msg.utime = 123456789
            big = os.urandom(100_000)
            lc.publish("COMLEARN_PY_STATUS", msg.encode())
            lc.publish("COMLEARN_PY_BIG", big)
            lc.publish("COMLEARN_PY_STATUS_X_NOT", b"")  # matches the regex in full too
            lc.publish("NOT_COMLEARN_PY_X", b"")  # does not: a full match is required
            for _ in range(50):
                if len(got) >= 3:
                    break
                lc.handle_timeout(100)
            self.assertEqual(len(got), 3, got)
            self.assertEqual(got[0][0], "COMLEARN_PY_STATUS")
            self.assertEqual(yumi_status_t.decode(got[0][1]).utime, 123456789)
            self.assertEqual(got[1], ("COMLEARN_PY_BIG", big))
            lc.unsubscribe(sub)
            lc.publish("COMLEARN_PY_STATUS", msg.encode())
            self.assertEqual(lc.handle_timeout(200), 1)  # received, dispatched to nobody
            self.assertEqual(len(got), 3)
        finally:
            lc.close()


if __name__ == "__main__":
    sys.exit(unittest.main(verbosity=2))
