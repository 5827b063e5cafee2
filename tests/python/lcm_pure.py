"""LCM logs and edsp's messages decoded in pure Python, message by message,
from the .lcm files themselves: an implementation independent of edsp's C++
(lcm-gen's codecs, logger/message_columns.h) for the tests to hold
edsp.read_log to, and the baseline its benchmark is measured against."""
import os
import re
import struct

_SCALARS = {"int8_t": "b", "boolean": "b", "byte": "B", "int16_t": ">h", "int32_t": ">i", "int64_t": ">q",
            "float": ">f", "double": ">d"}
_FIELD = re.compile(r"^\s*(\w+)\s+(\w+)((?:\s*\[\s*\d+\s*\])*)\s*;")


def parse_lcm_types(directory):
    """{type name: [(field, lcm type, dims)]} from every .lcm file there."""
    types = {}
    for name in sorted(os.listdir(directory)):
        if not name.endswith(".lcm"):
            continue
        text = open(os.path.join(directory, name), encoding="utf-8").read()
        text = re.sub(r"//[^\n]*", "", text)
        struct_name = re.search(r"struct\s+(\w+)", text).group(1)
        fields = []
        for line in text[text.index("{") + 1:].split("\n"):
            if line.strip().startswith("const"):
                continue
            m = _FIELD.match(line)
            if m:
                dims = tuple(int(d) for d in re.findall(r"\d+", m.group(3)))
                fields.append((m.group(2), m.group(1), dims))
        types[struct_name] = fields
    return types


def _read(data, offset, lcm_type, dims):
    if dims:
        values = []
        for _ in range(dims[0]):
            value, offset = _read(data, offset, lcm_type, dims[1:])
            values.append(value)
        return values, offset
    if lcm_type == "string":
        (length,) = struct.unpack_from(">i", data, offset)
        text = data[offset + 4:offset + 4 + length - 1].decode("utf-8", "replace")
        return text, offset + 4 + length
    fmt = _SCALARS[lcm_type]
    (value,) = struct.unpack_from(fmt, data, offset)
    return value, offset + struct.calcsize(fmt)


def decode(data, fields):
    """One message (fingerprint first, not checked) as a dict field -> value,
    field by field (the plain reading of the format)."""
    out, offset = {}, 8
    for name, lcm_type, dims in fields:
        out[name], offset = _read(data, offset, lcm_type, dims)
    return out


def _shaped(flat, dims):
    if len(dims) == 1:
        return list(flat)
    step = len(flat) // dims[0]
    return [_shaped(flat[i * step:(i + 1) * step], dims[1:]) for i in range(dims[0])]


class Decoder:
    """The same as decode(), faster: each run of fixed-size fields between
    strings read by one precompiled struct (the best pure Python does)."""

    def __init__(self, fields):
        self.steps = []  # ("string", name) or (struct, [(name, count, dims)])
        fmt, names = ">", []
        for name, lcm_type, dims in fields:
            if lcm_type == "string":
                if names:
                    self.steps.append((struct.Struct(fmt), names))
                    fmt, names = ">", []
                self.steps.append(("string", name))
                continue
            count = 1
            for d in dims:
                count *= d
            fmt += f"{count}{_SCALARS[lcm_type][-1]}"
            names.append((name, count, dims))
        if names:
            self.steps.append((struct.Struct(fmt), names))

    def __call__(self, data):
        out, offset = {}, 8
        for step, names in self.steps:
            if step == "string":
                (length,) = struct.unpack_from(">i", data, offset)
                out[names] = data[offset + 4:offset + 3 + length].decode("utf-8", "replace")
                offset += 4 + length
                continue
            values = step.unpack_from(data, offset)
            offset += step.size
            at = 0
            for name, count, dims in names:
                out[name] = _shaped(values[at:at + count], dims) if dims else values[at]
                at += count
        return out


def log_events(path):
    """(channel, timestamp_utime, data) of every whole event of an LCM log."""
    with open(path, "rb") as f:
        blob = f.read()
    offset = 0
    while offset + 28 <= len(blob):
        sync, _number, utime, channel_length, data_length = struct.unpack_from(">IqqII", blob, offset)
        if sync != 0xEDA1DA01:
            return
        start = offset + 28
        end = start + channel_length + data_length
        if end > len(blob):
            return
        yield blob[start:start + channel_length].decode(), utime, blob[start + channel_length:end]
        offset = end


def write_log(path, events):
    """An LCM log of (channel, utime, data) events."""
    with open(path, "wb") as f:
        for number, (channel, utime, data) in enumerate(events):
            c = channel.encode()
            f.write(struct.pack(">IqqII", 0xEDA1DA01, number, utime, len(c), len(data)) + c + data)
