#!/usr/bin/env python3
"""Writes the seed corpus of granular_fuzz into tests/fuzz/corpus: the shipped scenes, a scene
using every shape and emitter field, small valid .raw and .vox files (one model, a scene graph of
translated models, extra chunks, version 200) and snapshots (.gsnap) whose zstd frames are built
here from raw and RLE blocks (the format allows both; no zstd module needed). Deterministic; rerun after a format
change: python3 tests/fuzz/make_corpus.py"""

import random
import shutil
import struct
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE / "corpus"
SCENES = HERE.parent.parent / "assets" / "scenes"


def raw(nx, ny, nz, cells):
    return b"GRAW" + struct.pack("<IIII", 1, nx, ny, nz) + bytes(cells)


MASK64 = (1 << 64) - 1


def mix64(z):
    """splitmix64's finaliser (granular::mix64)."""
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
    return z ^ (z >> 31)


def hash_words(data):
    """granular::hash_words over every word of `data`: the summand of the grid hash."""
    padded = bytes(data) + bytes(-len(data) % 8)
    total = 0
    for i in range(len(padded) // 8):
        word = struct.unpack_from("<Q", padded, 8 * i)[0]
        total = (total + mix64((word + (i + 1) * 0x9E3779B97F4A7C15) & MASK64)) & MASK64
    return total


def faces_hash_term(faces):
    """granular::faces_hash_term of a face plane (int32 values): 0 when every value is 0."""
    if not any(faces):
        return 0
    total = 0
    for i, v in enumerate(faces):
        total = (total + mix64(((v & 0xFFFFFFFF) + (i + 1) * 0x9E3779B97F4A7C15) & MASK64)) & MASK64
    return mix64(total ^ 0x66616365706C616E)


def hash_cells(nx, ny, nz, cells, side=b"", faces=()):
    """granular::hash_cells: the grid hash a snapshot's header holds; with a side plane that holds a
    nonzero byte, plus granular::side_hash_term of it, and with a face plane, plus
    granular::faces_hash_term of it (WorldSnapshot::hash)."""
    total = hash_words(cells)
    if any(side):
        total = (total + mix64(hash_words(side) ^ 0x73696465706C616E)) & MASK64
    total = (total + faces_hash_term(faces)) & MASK64
    dims = nx | ny << 21 | nz << 42
    return mix64((mix64(dims ^ 0x6772616E756C6172) + total) & MASK64)


def zstd_frame(blocks, size):
    """A zstd frame of `blocks` ((type, payload): 0 raw bytes, 1 RLE (byte, count)) stating its
    content size in 8 bytes (single segment, no checksum)."""
    out = struct.pack("<I", 0xFD2FB528) + bytes([0xE0]) + struct.pack("<Q", size)
    for k, (kind, payload) in enumerate(blocks):
        last = 1 if k == len(blocks) - 1 else 0
        if kind == 0:
            out += (last | 0 << 1 | len(payload) << 3).to_bytes(3, "little") + payload
        else:
            byte, count = payload
            out += (last | 1 << 1 | count << 3).to_bytes(3, "little") + bytes([byte])
    return out


def bytes_hash(data):
    """The hash of a body section that snapshot_file_hash mixes in (version 6)."""
    h = mix64(len(data) ^ 0x424F444945535345)
    for i in range(0, len(data), 8):
        word = int.from_bytes(data[i:i + 8].ljust(8, b"\0"), "little")
        h = (mix64(h ^ word) + 0x9E3779B97F4A7C15) & MASK64
    return mix64(h)


def body_section(next_id, bodies):
    """A version-6 body section: the next handle, then per body (handle, shape, its 19 doubles: half
    extents, radius, half length, density, position, orientation w x y z, velocity, angular
    velocity, and its ascending cells) the record, the cell count and the cells as gaps."""
    out = struct.pack("<Q", next_id)
    for handle, shape, doubles, cells in bodies:
        out += struct.pack("<QII", handle, shape, 0) + struct.pack("<19d", *doubles) + struct.pack("<Q", len(cells))
        out += b"".join(struct.pack("<Q", c - (cells[k - 1] if k else 0)) for k, c in enumerate(cells))
    return out


def snapshot_file_hash(nx, ny, nz, cells_hash, version, tick, seed, tool_calls, fingerprint, rules, layout=3,
                       bodies=0, section=b""):
    """granular::snapshot_file_hash: the cells' hash alone in versions 1 and 2; from version 3 mixed
    with the header's fields; in version 6 with the body header's layout and count and the body
    section's hash too."""
    if version < 3:
        return cells_hash
    h = mix64(cells_hash ^ 0x47534E5048454144)
    for field in [version, nx, ny, nz, tick, seed, tool_calls, fingerprint, len(rules)] + list(rules):
        h = (mix64(h ^ field) + 0x9E3779B97F4A7C15) & MASK64
    if version == 6:
        for field in [layout, bodies, bytes_hash(section)]:
            h = (mix64(h ^ field) + 0x9E3779B97F4A7C15) & MASK64
    return mix64(h)


def snapshot(nx, ny, nz, cells, blocks, tick=100, seed=0, tool_calls=3, rules=b"inertial-24", fingerprint=0,
             version=1, frames=None, side=b"", faces=(), bodies=0, section=b""):
    """A snapshot file (docs/FORMATS.md) of `version` holding `cells` (and in version 4 the side
    plane `side`, in version 5 the face plane `faces`, after them; in version 6 the body section
    `section` of `bodies` bodies after those, its layout 3, 4 or 5 by the plane), compressed as
    `blocks` in one frame, or as `frames` (a list of (blocks, content bytes)) one after the other."""
    if frames is None:
        frames = [(blocks, len(cells) + len(side) + 4 * len(faces) + len(section))]
    body = b"".join(zstd_frame(b, size) for b, size in frames)
    layout = 5 if faces else 4 if side else 3
    check = snapshot_file_hash(nx, ny, nz, hash_cells(nx, ny, nz, cells, side, faces), version, tick, seed,
                               tool_calls, fingerprint, rules, layout, bodies, section)
    header = b"GSNP" + struct.pack("<IIIII", version, nx, ny, nz, len(rules)) + struct.pack(
        "<QQQQQQ", tick, seed, tool_calls, fingerprint, check, len(body))
    body_header = struct.pack("<IIQ", layout, bodies, len(section)) if version == 6 else b""
    return header + rules + body_header + body


def chunk(cid, content=b"", children=b""):
    return cid + struct.pack("<ii", len(content), len(children)) + content + children


def text(s):
    b = s.encode()
    return struct.pack("<i", len(b)) + b


def dictionary(pairs):
    return struct.pack("<i", len(pairs)) + b"".join(text(k) + text(v) for k, v in pairs)


def model(size, voxels):
    return chunk(b"SIZE", struct.pack("<iii", *size)) + chunk(
        b"XYZI", struct.pack("<i", len(voxels)) + b"".join(bytes(v) for v in voxels))


def ntrn(node, child, frame):
    return chunk(b"nTRN", struct.pack("<i", node) + dictionary([]) + struct.pack("<iiii", child, -1, 0, 1) +
                 dictionary(frame))


def ngrp(node, children):
    return chunk(b"nGRP", struct.pack("<i", node) + dictionary([]) + struct.pack("<i", len(children)) +
                 b"".join(struct.pack("<i", c) for c in children))


def nshp(node, model_id):
    return chunk(b"nSHP", struct.pack("<i", node) + dictionary([]) + struct.pack("<ii", 1, model_id) + dictionary([]))


def vox(children, version=150):
    return b"VOX " + struct.pack("<i", version) + chunk(b"MAIN", b"", children)


def main():
    if OUT.exists():
        shutil.rmtree(OUT)
    OUT.mkdir()
    for scene in sorted(SCENES.glob("*.json")):
        shutil.copy(scene, OUT / ("scene-" + scene.name))
    (OUT / "scene-every-field.json").write_text("""{
  "name": "every-field", "description": "every shape and emitter field", "comment": "ignored",
  "size": [1, 0.75, 0.5], "default_n": 32, "min_n": 8,
  "shapes": [
    {"type": "box", "material": "solid", "min": [0, 0, 0], "max": [1, 0.75, 0.0625]},
    {"type": "sphere", "material": "sand", "center": [0.5, 0.4, 0.3], "radius": 0.1, "only": "void"},
    {"type": "cylinder", "material": "liquid", "center": [0.25, 0.25], "radius": 0.1, "z0": 0.1, "z1": 0.2},
    {"type": "frustum", "material": "void", "center": [0.7, 0.5], "z0": 0.1, "z1": 0.3, "r0": 0.1, "r1": 0},
    {"type": "bowl", "material": "gravel", "center": [0.5, 0.4, 0.4], "radius": 0.2, "thickness_cells": 2},
    {"type": "bowl", "material": "gas", "center": [0.5, 0.4, 0.45], "radius": 0.1, "thickness": 0.05}
  ],
  "emitters": [
    {"center": [0.5, 0.4, 0.45], "radius": 0.05, "material": "granular", "rate_per_n2": 0.01, "start_per_n": 1, "stop_per_n": 2},
    {"center": [0.2, 0.2, 0.4], "radius": 0.03, "rate": 2, "start": 5, "stop": 50}
  ]
}
""")
    (OUT / "scene-minimal.json").write_text(
        '{"name":"m","description":"","size":[1,1,1],"default_n":4,"min_n":1,"shapes":[]}\n')

    rng = random.Random(7)
    (OUT / "grid-1x1x1.raw").write_bytes(raw(1, 1, 1, [2]))
    (OUT / "grid-all-states.raw").write_bytes(raw(4, 3, 2, [i % 8 for i in range(24)]))
    (OUT / "grid-16x16x8.raw").write_bytes(raw(16, 16, 8, [rng.choice([0, 0, 0, 1, 2]) for _ in range(16 * 16 * 8)]))

    palette = chunk(b"RGBA", bytes(range(256)) * 4)
    (OUT / "vox-one-model.vox").write_bytes(vox(model((4, 4, 4), [(0, 0, 0, 1), (1, 2, 3, 2), (3, 3, 3, 7)]) + palette))
    graph = (model((3, 3, 3), [(0, 0, 0, 1), (2, 2, 2, 2)]) + model((2, 5, 1), [(1, 4, 0, 3)]) +
             ntrn(0, 1, []) + ngrp(1, [2, 4]) + ntrn(2, 3, [("_t", "10 0 -2"), ("_r", "4")]) + nshp(3, 0) +
             ntrn(4, 5, [("_t", "-3 7 1")]) + nshp(5, 1) + chunk(b"LAYR", struct.pack("<i", 0) + dictionary([]) +
                                                                  struct.pack("<i", -1)))
    (OUT / "vox-scene-graph.vox").write_bytes(vox(graph, 200))
    extra = (chunk(b"PACK", struct.pack("<i", 1)) + model((2, 2, 2), [(1, 1, 1, 9), (0, 0, 0, 0)]) +
             chunk(b"MATL", struct.pack("<i", 1) + dictionary([("_type", "_diffuse")])) +
             chunk(b"ZZZZ", b"\x01\x02", chunk(b"YYYY", b"\x03")))
    (OUT / "vox-extra-chunks.vox").write_bytes(vox(extra))
    tiles = b""
    for k in range(2):
        tiles += model((256 if k == 0 else 44, 4, 3), [(k, 1, 2, 2)])
    tiles += ntrn(0, 1, []) + ngrp(1, [2, 4]) + ntrn(2, 3, [("_t", "-22 0 1")]) + nshp(3, 0) + \
        ntrn(4, 5, [("_t", "128 0 1")]) + nshp(5, 1)
    (OUT / "vox-two-tiles.vox").write_bytes(vox(tiles))

    cells = bytes([0x12, 2, 3, 0x93, 1, 0, 4, 5] * 3)  # sand and water with motion states
    (OUT / "snapshot-raw-block.gsnap").write_bytes(snapshot(4, 3, 2, cells, [(0, cells)]))
    floor = [1] * 64 + [0] * 192
    (OUT / "snapshot-rle-blocks.gsnap").write_bytes(
        snapshot(8, 8, 4, bytes(floor), [(1, (1, 64)), (1, (0, 192))], tick=7, seed=42, rules=b"paper"))
    mixed = bytes(rng.choice([0, 0, 1, 2, 0x1A]) for _ in range(100)) + bytes(156)
    (OUT / "snapshot-mixed-blocks.gsnap").write_bytes(
        snapshot(16, 4, 4, mixed, [(0, mixed[:100]), (1, (0, 156))], tool_calls=0))
    # Tall enough for 2 ranks of inertial-24 (halo 24): the distributed reader's inputs, one frame
    # per slab (version 2, and version 3 whose hash covers the header).
    tall = bytes([1] * 12 + [2] * 372) + bytes(384)
    slabs = [([(1, (1, 12)), (1, (2, 372))], 384), ([(1, (0, 384))], 384)]
    (OUT / "snapshot-slab-frames-v2.gsnap").write_bytes(snapshot(4, 3, 64, tall, None, version=2, frames=slabs))
    (OUT / "snapshot-slab-frames-v3.gsnap").write_bytes(snapshot(4, 3, 64, tall, None, version=3, frames=slabs))
    # Version 4: the side plane (liquid velocities, signed nibbles) after the cells.
    side = bytes([0, 0, 0x1F, 0, 0, 0, 0, 0] * 3)
    (OUT / "snapshot-side-plane-v4.gsnap").write_bytes(
        snapshot(4, 3, 2, cells, [(0, cells + side)], rules=b"inertial-24-momentum", version=4, side=side))
    # Version 5: the face plane (4 int32 per column: velocities, then fractions) after the cells.
    faces = [0] * 48
    faces[0], faces[12 + 1], faces[24 + 2], faces[36] = 700, -65536, 9000, -16384
    plane = struct.pack("<48i", *faces)
    (OUT / "snapshot-face-plane-v5.gsnap").write_bytes(
        snapshot(4, 3, 2, cells, [(0, cells + plane)], rules=b"inertial-24-shallow", version=5, faces=faces))
    # Version 6: a box of 700 kg/m^3 holding the two cells of state 7 (the body material), next
    # handle 3 (body 1 was removed).
    held = [17, 18]
    body_cells = bytes(7 if i in held else 2 if i < 12 else 0 for i in range(24))
    box = [1, 0.5, 0.5, 4, 4, 700, 2.0, 1.5, 1.5, 1, 0, 0, 0, 0, 0, -0.25, 0, 0, 0.01]
    section = body_section(3, [(2, 0, box, held)])
    (OUT / "snapshot-bodies-v6.gsnap").write_bytes(
        snapshot(4, 3, 2, body_cells, [(0, body_cells + section)], version=6, bodies=1, section=section))


if __name__ == "__main__":
    main()
