#!/usr/bin/env python3
"""Writes the seed corpora fuzz/corpus/<target>/ (committed; rerun only to change them).

Seeds are small (at most a few KB): the small asset files as they are, cuts of the large ones (a
few faces with the vertices they use, renumbered), and the hand-made files of tests/import.rs.
The .vgeo seeds are built from small meshes by the vgeo binary. Only files whose licence lets
them live in this repository are used (see README.md); the CGAL OFF files of the shared assets
(GPL) are replaced by hand-made files with the same traits.

usage: fuzz/make_corpus.py ASSETS_DIR SHARED_ASSETS_DIR VGEO_BINARY
  e.g. fuzz/make_corpus.py assets /work/shared/assets target/debug/vgeo
"""

import base64
import json
import os
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")


def put(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    assert len(data) <= 8192, (target, name, len(data))
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def f32s(vals):
    return b"".join(struct.pack("<f", v) for v in vals)


# --- OBJ ---------------------------------------------------------------------------------------

def obj_cut(text, faces):
    """The first `faces` faces of an OBJ with the v/vt/vn they use, renumbered."""
    vs, vts, vns, fs = [], [], [], []
    for line in text.splitlines():
        t = line.split()
        if not t:
            continue
        {"v": vs, "vt": vts, "vn": vns, "f": fs}.get(t[0], []).append(t[1:])
    maps = [{}, {}, {}]
    out_f = []
    for f in fs[:faces]:
        corners = []
        for c in f:
            parts = c.split("/")
            new = []
            for k, p in enumerate(parts):
                if p == "":
                    new.append("")
                    continue
                m = maps[k]
                m.setdefault(int(p), len(m) + 1)
                new.append(str(m[int(p)]))
            corners.append("/".join(new))
        out_f.append("f " + " ".join(corners))
    out = []
    for k, (tag, src) in enumerate((("v", vs), ("vt", vts), ("vn", vns))):
        for old, _ in sorted(maps[k].items(), key=lambda kv: kv[1]):
            out.append(tag + " " + " ".join(src[old - 1]))
    return "\n".join(out + out_f) + "\n"


def u_shape_obj():
    # tests/import.rs: a U-shaped concave octagon with UVs, normals and a material library.
    pts = [(0, 0, 0), (3, 0, 0), (3, 3, 0), (2, 3, 0), (2, 1, 0), (1, 1, 0), (1, 3, 0), (0, 3, 0)]
    s = "".join(f"v {x} {y} {z}\nvt 0.5 0.5\nvn 0 0 1\n" for x, y, z in pts)
    return s + "mtllib m.mtl\nusemtl a\nf 1/1/1 2/2/2 3/3/3 4/4/4 5/5/5 6/6/6 7/7/7 8/8/8\n"


def obj_features():
    # Negative (relative) indices, groups, objects, smoothing, a line and a point, v-only and v//vn
    # corners, an unknown material, a second material and a vertex colour.
    return (
        "# features\no first\ng side\ns 1\nmtllib missing.mtl\n"
        "v 0 0 0\nv 1 0 0 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nvt 1 0\nvt 1 1\n"
        "usemtl red\nf -4/1/1 -3/2/1 -2/3/1\nf 1//1 3//1 4//1\n"
        "o second\ng top\nusemtl blue\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 5 6 7\n"
        "l 1 2\np 3\nf 5/1 7/3 6/2\n"
    )


# --- PLY ---------------------------------------------------------------------------------------

def binary_ply(big_endian=False):
    e = ">" if big_endian else "<"
    head = (
        "ply\nformat binary_%s_endian 1.0\ncomment test\nelement vertex 6\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nproperty float s\nproperty float t\n"
        "element face 2\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n"
        "property int vertex2\nend_header\n" % ("big" if big_endian else "little")
    ).encode()
    v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0.5, 0), (9, 9, 9)]
    b = bytearray(head)
    for i, p in enumerate(v):
        b += struct.pack(e + "fffBff", *p, 200, i * 0.1, 0.25)
    b += struct.pack(e + "B4i", 4, 0, 1, 2, 3)
    b += struct.pack(e + "B3i", 3, 1, 4, 2)
    b += struct.pack(e + "2i", 0, 1)
    return bytes(b)


def binary_layouts_ply(big_endian=False):
    """What the importer's binary fast path reads: every scalar type, normals, uvs by an alias,
    colours, a list in the vertex, quads, a concave hexagon and a 2-corner face with a ushort or
    uint count, other properties and lists in the face, elements before and after."""
    e = ">" if big_endian else "<"
    count, ct = ("H", "ushort") if big_endian else ("I", "uint")
    head = (
        "ply\nformat binary_%s_endian 1.0\nobj_info layouts\nelement material 1\n"
        "property list uchar char name\nproperty float shininess\nelement vertex 8\n"
        "property double x\nproperty float y\nproperty short z\nproperty char nx\n"
        "property char ny\nproperty char nz\nproperty uchar red\nproperty uchar green\n"
        "property uchar blue\nproperty float texture_u\nproperty ushort texture_v\n"
        "property list uchar int8 tags\nelement face 4\nproperty uchar flags\n"
        "property list %s uint vertex_indices\nproperty list uchar float texcoord\n"
        "element edge 1\nproperty int vertex1\nproperty uint vertex2\nend_header\n"
        % ("big" if big_endian else "little", ct)
    ).encode()
    v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 2, 0), (0.5, 2, 0), (3, 3, 1)]
    b = bytearray(head)
    b += struct.pack(e + "B3bf", 3, 97, 98, 99, 0.5)
    for i, p in enumerate(v):
        b += struct.pack(e + "dfh3b3BfH", p[0], p[1], int(p[2]), 0, 0, 1, 200, i, 7, i * 0.125, i % 2)
        b += struct.pack(e + "B%db" % (i % 3), i % 3, *range(i % 3))
    for f in [(0, 1, 2, 3), (0, 4, 5, 6, 3, 2), (1, 2), (2, 5, 7)]:
        b += struct.pack(e + "B" + count + "%dI" % len(f), 1, len(f), *f)
        b += struct.pack(e + "B2f", 2, 0.5, 0.25)
    b += struct.pack(e + "iI", 0, 1)
    return bytes(b)


def ascii_ply():
    return (
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\n"
        "property double z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 2\n"
        "property list uint8 uint32 vertex_index\nend_header\n"
        "0 0 0 0 0 1\n2 1 0 0 0 1\n0 2 0 0 0 1\n1 1 0 0 0 1\n-1 1 0 0 0 1\n0 0 5 0 0 1\n"
        "1 0 5 0 0 1\n0 1 5 0 0 1\n4 0 1 2 3\n3 5 6 7\n"
    )


def ply_cut(text, faces):
    """The bunny's header with the first `faces` faces and the vertices they use, renumbered."""
    lines = text.splitlines()
    end = lines.index("end_header")
    header = lines[: end + 1]
    nv = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    verts = lines[end + 1 : end + 1 + nv]
    fl = lines[end + 1 + nv : end + 1 + nv + faces]
    m = {}
    out_f = []
    for l in fl:
        t = l.split()
        idx = [m.setdefault(int(i), len(m)) for i in t[1 : 1 + int(t[0])]]
        out_f.append(" ".join([t[0]] + [str(i) for i in idx]))
    out_v = [verts[old] for old, _ in sorted(m.items(), key=lambda kv: kv[1])]
    header = [
        f"element vertex {len(out_v)}" if l.startswith("element vertex")
        else f"element face {len(out_f)}" if l.startswith("element face")
        else l
        for l in header
    ]
    return "\n".join(header + out_v + out_f) + "\n"


# --- STL ---------------------------------------------------------------------------------------

def binary_stl():
    b = bytearray(80)
    b[:5] = b"solid"
    b += struct.pack("<I", 2)
    for tri in [((0, 0, 0), (1, 0, 0), (1, 1, 0)), ((0, 0, 0), (1, 1, 0), (0, 1, 0))]:
        b += f32s([0, 0, 0]) + f32s([c for p in tri for c in p]) + struct.pack("<H", 0)
    return bytes(b)


def binary_stl_cut(data, tris):
    return data[:80] + struct.pack("<I", tris) + data[84 : 84 + 50 * tris]


def ascii_stl_cut(text, facets):
    out, n = [], 0
    for line in text.splitlines():
        if n == facets:
            break
        out.append(line)
        if line.strip() == "endfacet":
            n += 1
    return "\n".join(out + ["endsolid"]) + "\n"


# --- OFF ---------------------------------------------------------------------------------------

def off_sphere(rings=6, segments=8, holes=(3, 17, 18)):
    """A UV sphere of quads (triangles at the poles) with a few faces left out: holes."""
    import math
    verts = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        t = math.pi * r / rings
        for k in range(segments):
            p = 2 * math.pi * k / segments
            verts.append((math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)))
    verts.append((0.0, 0.0, -1.0))
    ring = lambda r, k: 1 + (r - 1) * segments + k % segments
    faces = [(0, ring(1, k), ring(1, k + 1)) for k in range(segments)]
    for r in range(1, rings - 1):
        for k in range(segments):
            faces.append((ring(r, k), ring(r + 1, k), ring(r + 1, k + 1), ring(r, k + 1)))
    last = len(verts) - 1
    faces += [(ring(rings - 1, k + 1), ring(rings - 1, k), last) for k in range(segments)]
    faces = [f for i, f in enumerate(faces) if i not in holes]
    out = ["OFF", "%d %d 0" % (len(verts), len(faces))]
    out += ["%.6g %.6g %.6g" % v for v in verts]
    out += [" ".join([str(len(f))] + [str(i) for i in f]) for f in faces]
    return "\n".join(out) + "\n"


def off_own():
    """Small hand-made OFF files with the traits of the CGAL test files the import tests read
    (those are GPL and stay out of the repository)."""
    return {
        # An open strip folded back over itself.
        "folded_strip.off": "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n"
        "0 1 0.01\n1 1 0.01\n3 0 1 3\n3 0 3 2\n3 2 3 5\n3 2 5 4\n3 4 5 7\n3 4 7 6\n",
        # Two rows of quads whose shared edge has coincident but distinct vertices.
        "quads_unstitched.off": "OFF\n12 4 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n"
        "0 1 0\n1 1 0\n2 1 0\n0 2 0\n1 2 0\n2 2 0\n4 0 1 4 3\n4 1 2 5 4\n4 6 7 10 9\n"
        "4 7 8 11 10\n",
        # Collinear (zero-area) triangles among good ones.
        "collinear.off": "OFF\n6 4 0\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n1 1 0\n2 1 0\n"
        "3 0 1 2\n3 1 2 3\n3 0 1 4\n3 1 5 4\n",
        # A tetrahedron and a separate triangle cutting through it.
        "tetra_and_triangle.off": "OFF\n7 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n-1 0.2 0.2\n"
        "2 0.2 0.2\n0.2 2 0.2\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 4 5 6\n",
    }


def off_variants():
    # COFF with colours on vertices and faces, NOFF with normals, STOFF, the counts on the header
    # line, comments and a pentagon.
    return {
        "coff.off": "COFF\n# colours\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n"
        "0 1 0 9 9 9 255\n3 0 1 2 1 0 0\n3 0 2 3 0 1 0\n",
        "noff.off": "NOFF 5 1 0\n0 0 0 0 0 1\n2 0 0 0 0 1\n2 2 0 0 0 1\n1 1 0 0 0 1\n0 2 0 0 0 1\n"
        "5 0 1 2 3 4\n",
        "stoff.off": "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n",
    }


# --- glTF --------------------------------------------------------------------------------------

def gltf_scene(extra_root=""):
    """tests/import.rs gltf_scene: (bin, json with BUFFER_URI to replace)."""
    b = f32s([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]) + f32s([0, 0, 1] * 4)
    b += struct.pack("<8H", 0, 1, 2, 3, 0, 1, 3, 2) + f32s([0, 0, 5, 1, 0, 5, 0, 1, 5])
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "Root", "scale": [2, 2, 2], "children": [1, 2, 3]},
            {"name": "Child", "translation": [10, 0, 0], "mesh": 0},
            {"name": "Mirror", "scale": [-1, 1, 1], "mesh": 0},
            {"name": "Tri", "mesh": 1},
        ],
        "meshes": [
            {"name": "square", "primitives": [
                {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "mode": 5},
                {"attributes": {"POSITION": 0}, "mode": 0},
                {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 3, "mode": 6},
            ]},
            {"name": "tri", "primitives": [{"attributes": {"POSITION": 4}}]},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 4, "type": "SCALAR"},
            {"bufferView": 3, "componentType": 5123, "count": 4, "type": "SCALAR"},
            {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 5], "max": [1, 1, 5]},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 8},
            {"buffer": 0, "byteOffset": 104, "byteLength": 8},
            {"buffer": 0, "byteOffset": 112, "byteLength": 36},
        ],
        "buffers": [{"byteLength": 148}],
    }
    doc.update(extra_root)
    return b, doc


def data_uri(b):
    return "data:application/octet-stream;base64," + base64.b64encode(b).decode()


def embed(doc, b):
    doc = json.loads(json.dumps(doc))
    doc["buffers"] = [{"byteLength": len(b), "uri": data_uri(b)}]
    return json.dumps(doc, separators=(",", ":"))


def glb(doc, b):
    j = json.dumps(doc, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    b = b + b"\0" * (-len(b) % 4)
    out = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(j) + 8 + len(b))
    out += struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(b), b"BIN\0") + b
    return out


def glb_buffers(doc, b):
    doc = json.loads(json.dumps(doc))
    doc["buffers"] = [{"byteLength": len(b)}]
    return glb(doc, b)


def textured_extras():
    # Materials with all three textures: a file image, an image in a buffer view, a data URI; a
    # sampler; KHR_materials_emissive_strength; a camera node and a matrix.
    return {
        "materials": [
            {"name": "m", "pbrMetallicRoughness": {
                "baseColorFactor": [1, 0.5, 0.25, 1], "metallicFactor": 0.5, "roughnessFactor": 0.3,
                "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}},
             "normalTexture": {"index": 2, "scale": 1},
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
        ],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}, {"source": 2}],
        "samplers": [{"magFilter": 9729, "wrapS": 10497}],
        "images": [{"uri": "tex%20ture.png"}, {"bufferView": 0, "mimeType": "image/png"},
                   {"uri": "data:image/png;base64,iVBORw0KGgo="}],
        "extensionsUsed": ["KHR_materials_emissive_strength"],
    }


def sparse_doc():
    # A sparse accessor without a buffer view (zeros plus substitutions) and a sparse accessor over
    # a buffer view; u8 and u32 indices; a second scene; normalized UVs as u16.
    b = f32s([0, 0, 0, 1, 0, 0, 0, 1, 0])  # 0..36 positions
    b += struct.pack("<3B", 0, 1, 2) + b"\0"  # 36..40 u8 indices
    b += struct.pack("<2I", 1, 2)  # 40..48 sparse indices
    b += f32s([2, 0, 0, 0, 2, 0])  # 48..72 sparse values
    b += struct.pack("<6H", 0, 0, 65535, 0, 0, 65535)  # 72..84 uvs
    b += struct.pack("<3I", 2, 1, 0)  # 84..96 u32 indices
    doc = {
        "asset": {"version": "2.0"},
        "scene": 1,
        "scenes": [{"nodes": [0]}, {"nodes": [1, 0]}],
        "nodes": [{"mesh": 0, "rotation": [0, 0, 0.7071068, 0.7071068]},
                  {"mesh": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 1, "TEXCOORD_0": 3}, "indices": 2}]},
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 4}]},
        ],
        "accessors": [
            {"componentType": 5126, "count": 3, "type": "VEC3",
             "sparse": {"count": 2, "indices": {"bufferView": 1, "componentType": 5125},
                        "values": {"bufferView": 2}}},
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "sparse": {"count": 2, "indices": {"bufferView": 1, "componentType": 5125},
                        "values": {"bufferView": 2}}},
            {"bufferView": 3, "componentType": 5121, "count": 3, "type": "SCALAR"},
            {"bufferView": 4, "componentType": 5123, "normalized": True, "count": 3, "type": "VEC2"},
            {"bufferView": 5, "componentType": 5125, "count": 3, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 40, "byteLength": 8},
            {"buffer": 0, "byteOffset": 48, "byteLength": 24},
            {"buffer": 0, "byteOffset": 36, "byteLength": 3},
            {"buffer": 0, "byteOffset": 72, "byteLength": 12, "byteStride": 4},
            {"buffer": 0, "byteOffset": 84, "byteLength": 12},
        ],
        "buffers": [{"byteLength": len(b)}],
    }
    return doc, b


def main():
    assets, shared, vgeo = sys.argv[1:4]
    hard = os.path.join(shared, "hard")

    # OBJ
    put("import_obj", "concave_polygon.obj", read(os.path.join(hard, "concave_polygon.obj")))
    spot = read(os.path.join(assets, "spot.obj")).decode()
    put("import_obj", "spot_cut.obj", obj_cut(spot, 24))
    put("import_obj", "u_shape.obj", u_shape_obj())
    put("import_obj", "features.obj", obj_features())

    # PLY
    put("import_ply", "binary_le.ply", binary_ply())
    put("import_ply", "binary_be.ply", binary_ply(big_endian=True))
    put("import_ply", "ascii.ply", ascii_ply())
    put("import_ply", "binary_layouts_le.ply", binary_layouts_ply())
    put("import_ply", "binary_layouts_be.ply", binary_layouts_ply(big_endian=True))
    bunny = read(os.path.join(assets, "bunny.ply")).decode()
    put("import_ply", "bunny_cut.ply", ply_cut(bunny, 24))

    # STL
    put("import_stl", "triangle_with_two_solids.stl",
        read(os.path.join(hard, "triangle_with_two_solids.stl")))
    put("import_stl", "square_binary.stl", binary_stl())
    put("import_stl", "spider_cut.stl",
        binary_stl_cut(read(os.path.join(hard, "Spider_binary.stl")), 24))
    put("import_stl", "sphere_with_hole_cut.stl",
        ascii_stl_cut(read(os.path.join(hard, "sphereWithHole.stl")).decode(), 8))

    # OFF
    for n, text in off_own().items():
        put("import_off", n, text)
    put("import_off", "sphere_with_holes.off", off_sphere())
    for n, text in off_variants().items():
        put("import_off", n, text)

    # glTF / GLB
    b, doc = gltf_scene()
    put("import_gltf", "scene.gltf", embed(doc, b))
    b2, doc2 = gltf_scene(textured_extras())
    put("import_gltf", "textured.gltf", embed(doc2, b2))
    sdoc, sb = sparse_doc()
    put("import_gltf", "sparse.gltf", embed(sdoc, sb))
    ioor = os.path.join(shared, "invalid", "IndexOutOfRange")
    idoc = json.loads(read(os.path.join(ioor, "IndexOutOfRange.gltf")))
    ibin = read(os.path.join(ioor, "IndexOutOfRange.bin"))
    put("import_gltf", "index_out_of_range.gltf", embed(idoc, ibin))
    lantern = json.loads(read(os.path.join(shared, "gltf", "Lantern", "Lantern.gltf")))
    put("import_gltf", "lantern_external_buffer.gltf",
        json.dumps(lantern, separators=(",", ":")))

    put("import_glb", "scene.glb", glb_buffers(doc, b))
    put("import_glb", "textured.glb", glb_buffers(doc2, b2))
    put("import_glb", "sparse.glb", glb_buffers(sdoc, sb))
    put("import_glb", "index_out_of_range.glb", glb_buffers(idoc, ibin))
    put("import_glb", "box_with_infinites.glb",
        read(os.path.join(shared, "invalid", "BoxWithInfinites.glb")))

    # .vgeo: small meshes built with default options, and one with several levels.
    with tempfile.TemporaryDirectory() as tmp:
        own = {"sphere_with_holes.off": off_sphere(), "u_shape.obj": u_shape_obj()}
        own.update(off_own())
        for n, text in own.items():
            with open(os.path.join(tmp, n), "w") as f:
                f.write(text)
        builds = [
            ("tetra_and_triangle.vgeo", os.path.join(tmp, "tetra_and_triangle.off"), []),
            ("quads_unstitched.vgeo", os.path.join(tmp, "quads_unstitched.off"), []),
            ("u_shape.vgeo", os.path.join(tmp, "u_shape.obj"), []),
            ("sphere_levels.vgeo", os.path.join(tmp, "sphere_with_holes.off"),
             ["--max-triangles", "16", "--group-min", "2", "--group-max", "4",
              "--root-triangles", "0"]),
        ]
        textured = os.path.join(tmp, "textured.gltf")
        with open(textured, "w") as f:
            f.write(embed(doc2, b2))
        builds.append(("textured.vgeo", textured, []))
        for name, src, extra in builds:
            out = os.path.join(tmp, name)
            subprocess.run([vgeo, "build", src, "-o", out, "--threads", "1"] + extra,
                           check=True, stdout=subprocess.DEVNULL)
            put("load_vgeo", name, read(out))


if __name__ == "__main__":
    main()
