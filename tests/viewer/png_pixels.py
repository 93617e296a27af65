"""Reads the pixels of a PNG the sandbox wrote (8-bit RGB or RGBA, not interlaced: what
stb_image_write produces), with the standard library alone, and finds squares of one colour in it."""

import struct
import zlib


def png_size(path):
    """(width, height) of the PNG at `path`, from its header."""
    with open(path, "rb") as f:
        data = f.read(24)
    if data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        raise ValueError(f"{path}: not a PNG")
    return struct.unpack(">II", data[16:24])


def read_png(path, max_width=None, max_height=None):
    """(width, height, rows) of the image's top-left max_width x max_height pixels (all by default):
    rows[y] is a bytes object of width * 4 RGBA bytes. (A PNG row's filters look only left and up,
    so the top-left corner decodes on its own.)"""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    offset, chunks, header = 8, [], None
    while offset < len(data):
        length, kind = struct.unpack(">I4s", data[offset:offset + 8])
        body = data[offset + 8:offset + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            chunks.append(body)
        offset += 12 + length
    full_width, full_height, depth, colour_type, _, _, interlace = header
    if depth != 8 or colour_type not in (2, 6) or interlace:
        raise ValueError(f"{path}: only 8-bit RGB or RGBA, not interlaced, is read here")
    channels = 4 if colour_type == 6 else 3
    width = min(full_width, max_width or full_width)
    height = min(full_height, max_height or full_height)
    raw = zlib.decompress(b"".join(chunks))
    stride, used = full_width * channels, width * channels
    rows, previous = [], bytearray(used)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + used])
        for i in range(used):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else corner)) & 255
        previous = line
        rgba = bytes(line) if channels == 4 else b"".join(bytes(line[i:i + 3]) + b"\xff" for i in range(0, used, 3))
        rows.append(rgba)
    return width, height, rows


def has_square_of_colour(png, rgb, size):
    """True when the image holds a size x size square of opaque pixels of exactly colour `rgb`."""
    _, _, rows = png
    pattern = bytes(rgb) + b"\xff"
    run = pattern * size
    tall = {}  # x -> consecutive rows, up to this one, with `size` pixels of the colour from x
    for row in rows:
        found, start = set(), row.find(run)
        while start >= 0:
            if start % 4 == 0:
                found.add(start // 4)
            start = row.find(run, start + 1)
        tall = {x: tall.get(x, 0) + 1 for x in found}
        if any(count >= size for count in tall.values()):
            return True
    return False
