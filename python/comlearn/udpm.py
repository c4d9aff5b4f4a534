"""comlearn.udpm - LCM's UDP multicast transport in plain Python, for comlearn's message types.

The message classes of this package (``from comlearn import yumi_status_t``) only encode and
decode bytes; a client also needs a transport. With LCM's own Python module (``import lcm``,
not packaged by Debian 12) use ``lcm.LCM(url)``. Without it, ``comlearn.udpm.LCM(url)`` speaks
the same wire protocol for ``udpm://`` URLs with the same calls::

    from comlearn import udpm, yumi_status_t
    lc = udpm.connect("udpm://239.255.76.67:7667?ttl=0")   # lcm.LCM when importable
    lc.subscribe("YUMI_STATUS", lambda ch, data: print(yumi_status_t.decode(data).utime))
    while True:
        lc.handle_timeout(100)

The protocol (LCM's lcm_udpm.c): one datagram per message of at most 65 499 bytes of channel and
payload, "LC02" + sequence number + channel + NUL + payload (big endian); longer messages are
fragments, "LC03" + sequence number + payload size + fragment offset + fragment number + count,
the channel (NUL-terminated) in front of the first fragment's data. ``publish`` sends short
messages and fragments; the receiver reassembles fragments per sender and sequence number.
comlearn's messages are all short. Only udpm URLs are served (no memq://, file://, tcpq://).

One thread per instance, as with LCM. Everything fails with ValueError (bad URL, channel,
datagram) or OSError (sockets).
"""

import re
import select
import socket
import struct
import urllib.parse

__all__ = ["LCM", "connect", "parse_url", "encode_datagrams", "Reassembler"]

MAGIC_SHORT = 0x4C433032  # "LC02"
MAGIC_LONG = 0x4C433033  # "LC03"
SHORT_MAX = 65499  # channel + NUL + payload in one datagram (LCM on Linux)
FRAGMENT_MAX = 65487  # payload bytes per fragment
CHANNEL_MAX = 63  # LCM_MAX_CHANNEL_NAME_LENGTH
MESSAGE_MAX = 1 << 28  # LCM_MAX_MESSAGE_SIZE: larger fragmented messages are refused
DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"


def parse_url(url):
    """(group, port, ttl, recv_buf_size or None) of a udpm URL; ValueError naming the problem."""
    u = urllib.parse.urlsplit(url)
    if u.scheme != "udpm":
        raise ValueError("comlearn.udpm serves udpm:// URLs only, not %r" % url)
    host, sep, port = u.netloc.rpartition(":")
    if not sep or not host:
        raise ValueError("udpm URL %r has no ADDRESS:PORT" % url)
    try:
        group = socket.inet_aton(host)
        port = int(port)
    except (OSError, ValueError):
        raise ValueError("udpm URL %r: %r is not IPv4-address:port" % (url, u.netloc)) from None
    if not 224 <= group[0] <= 239:
        raise ValueError("udpm URL %r: %s is not a multicast address" % (url, host))
    if not 0 < port < 65536:
        raise ValueError("udpm URL %r: port %d out of range" % (url, port))
    ttl, rbuf = 0, None
    for key, vals in urllib.parse.parse_qs(u.query, keep_blank_values=True).items():
        if key not in ("ttl", "recv_buf_size"):
            raise ValueError("udpm URL %r: unknown option %r" % (url, key))
        try:
            value = int(vals[-1])
        except ValueError:
            raise ValueError("udpm URL %r: %s=%r is not a number" % (url, key, vals[-1])) from None
        if key == "ttl":
            ttl = value
        else:
            rbuf = value
    if not 0 <= ttl <= 255:
        raise ValueError("udpm URL %r: ttl %d out of range 0..255" % (url, ttl))
    if rbuf is not None and rbuf <= 0:
        raise ValueError("udpm URL %r: recv_buf_size must be positive" % url)
    return host, port, ttl, rbuf


def _channel_bytes(channel):
    c = channel.encode("utf-8")
    if not c or len(c) > CHANNEL_MAX or b"\0" in c:
        raise ValueError("LCM channel %r: 1..%d bytes without NUL" % (channel, CHANNEL_MAX))
    return c


def encode_datagrams(channel, data, seqno):
    """The datagrams LCM sends for one message, as a list of bytes."""
    c = _channel_bytes(channel) + b"\0"
    data = bytes(data)
    seqno &= 0xFFFFFFFF
    if len(c) + len(data) <= SHORT_MAX:
        return [struct.pack(">II", MAGIC_SHORT, seqno) + c + data]
    payload = len(c) + len(data)
    count = (payload + FRAGMENT_MAX - 1) // FRAGMENT_MAX
    if count > 65535:
        raise ValueError("LCM message of %d bytes is too long" % len(data))
    out, offset = [], 0
    for k in range(count):
        room = FRAGMENT_MAX - (len(c) if k == 0 else 0)
        chunk = data[offset : offset + room]
        hdr = struct.pack(">IIIIHH", MAGIC_LONG, seqno, len(data), offset, k, count)
        out.append(hdr + (c if k == 0 else b"") + chunk)
        offset += len(chunk)
    return out


class Reassembler:
    """Datagrams in, (channel, payload) out: short messages at once, fragmented ones complete."""

    def __init__(self, max_pending=64):
        self._pending = {}  # (sender, seqno) -> [size, channel, bytearray, numbers not yet seen]
        self._max_pending = max_pending
        self.discarded = 0  # datagrams that were not LCM's, or inconsistent fragments

    def feed(self, datagram, sender=None):
        """(channel, bytes) when datagram completes a message, else None."""
        if len(datagram) < 8:
            self.discarded += 1
            return None
        magic, seqno = struct.unpack_from(">II", datagram)
        if magic == MAGIC_SHORT:
            end = datagram.find(b"\0", 8)
            if end < 0 or end - 8 > CHANNEL_MAX or end == 8:
                self.discarded += 1
                return None
            return datagram[8:end].decode("utf-8", "replace"), bytes(datagram[end + 1 :])
        if magic != MAGIC_LONG or len(datagram) < 20:
            self.discarded += 1
            return None
        size, offset, number, count = struct.unpack_from(">IIHH", datagram, 8)
        body = datagram[20:]
        key = (sender, seqno)
        entry = self._pending.get(key)
        if entry is not None and entry[0] != size:
            del self._pending[key]  # a stale message with this seqno
            entry = None
        if size > MESSAGE_MAX or count == 0 or number >= count:
            self.discarded += 1
            return None
        if entry is None:
            if len(self._pending) >= self._max_pending:
                self._pending.pop(next(iter(self._pending)))  # the oldest
            entry = self._pending[key] = [size, None, bytearray(size), set(range(count))]
        if number not in entry[3]:
            self.discarded += 1  # a repeated fragment, or one of another count
            return None
        if number == 0:
            end = body.find(b"\0")
            if end <= 0 or end > CHANNEL_MAX:
                self.discarded += 1
                del self._pending[key]
                return None
            entry[1] = body[:end].decode("utf-8", "replace")
            body = body[end + 1 :]
        if offset + len(body) > size:
            self.discarded += 1
            del self._pending[key]
            return None
        entry[2][offset : offset + len(body)] = body
        entry[3].discard(number)
        if entry[3]:
            return None
        del self._pending[key]
        if entry[1] is None:
            self.discarded += 1
            return None
        return entry[1], bytes(entry[2])


class _Subscription:
    def __init__(self, pattern, handler):
        self.channel = pattern
        self.regex = re.compile(pattern)
        self.handler = handler


class LCM:
    """LCM over udpm, the subset of lcm.LCM that clients use: publish, subscribe, unsubscribe,
    handle, handle_timeout, fileno. Like LCM, the receive socket opens on the first subscribe."""

    def __init__(self, url=DEFAULT_URL):
        self.url = url
        self._group, self._port, self._ttl, self._rbuf = parse_url(url)
        self._send = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        self._send.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, self._ttl)
        self._send.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
        self._recv = None
        self._seqno = 0
        self._subs = []
        self._asm = Reassembler()

    def _open_receive(self):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        if hasattr(socket, "SO_REUSEPORT"):
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
        if self._rbuf:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, self._rbuf)
        s.bind(("", self._port))
        mreq = socket.inet_aton(self._group) + struct.pack("=I", socket.INADDR_ANY)
        s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, mreq)
        s.setblocking(False)
        self._recv = s

    def publish(self, channel, data):
        for d in encode_datagrams(channel, data, self._seqno):
            self._send.sendto(d, (self._group, self._port))
        self._seqno = (self._seqno + 1) & 0xFFFFFFFF

    def subscribe(self, channel, handler):
        """handler(channel, data) for every message whose channel matches the regex `channel`
        in full (LCM's rule). Returns the subscription for unsubscribe."""
        if self._recv is None:
            self._open_receive()
        sub = _Subscription(channel, handler)
        self._subs.append(sub)
        return sub

    def unsubscribe(self, sub):
        self._subs.remove(sub)

    def fileno(self):
        if self._recv is None:
            self._open_receive()
        return self._recv.fileno()

    def _dispatch_ready(self):
        n = 0
        while True:
            try:
                d, sender = self._recv.recvfrom(65536)
            except BlockingIOError:
                return n
            msg = self._asm.feed(d, sender)
            if msg is None:
                continue
            channel, data = msg
            for sub in list(self._subs):
                if sub.regex.fullmatch(channel):
                    sub.handler(channel, data)
            n += 1

    def handle_timeout(self, timeout_ms):
        """Dispatch what arrives within timeout_ms: the number of messages (0 on a timeout)."""
        if self._recv is None:
            self._open_receive()
        ready, _, _ = select.select([self._recv], [], [], max(0, timeout_ms) / 1000.0)
        return self._dispatch_ready() if ready else 0

    def handle(self):
        """Block until at least one message was dispatched."""
        while self.handle_timeout(1000) == 0:
            pass

    def close(self):
        for s in (self._send, self._recv):
            if s is not None:
                s.close()
        self._send = self._recv = None


def connect(url=DEFAULT_URL):
    """lcm.LCM(url) when LCM's Python module is importable, else comlearn.udpm.LCM(url)."""
    try:
        import lcm  # noqa: PLC0415 - optional

        return lcm.LCM(url)
    except ImportError:
        return LCM(url)
