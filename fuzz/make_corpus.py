#!/usr/bin/env python3
"""Write the seed corpora of cloth.h's fuzz harnesses: fuzz/corpus/{obj,ply,vtk,off}/.

    python3 fuzz/make_corpus.py

Each corpus holds small valid files that reach every feature of its reader (every OBJ face
form, every PLY encoding and property type, both VTK cell layouts in ASCII and BINARY, OFF
variants) and small invalid ones that reach its errors (bad numbers, indices out of range,
NaN, truncated binary data, counts far larger than the file). The output is deterministic;
no third-party modules are needed.
"""
import base64
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(kind, name, data):
    folder = os.path.join(HERE, "corpus", kind)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode("ascii")
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def grid(nx, ny):
    pts = [(0.1 * i - 0.3, 0.05 * ((i * 7 + j * 3) % 5) / 3.0, j / 3.0) for j in range(ny) for i in range(nx)]
    tris = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i
            tris += [(a, a + 1, a + nx + 1), (a, a + nx + 1, a + nx)]
    return pts, tris


# ---- OBJ --------------------------------------------------------------------------------

def obj_corpus():
    write("obj", "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write("obj", "face_forms.obj",
          "# every face form\nmtllib m.mtl\no sheet\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\n"
          "vt 0.25 0.5\nvt 0.75\nvn 0 0 1\ng g\nusemtl m\ns off\nf 1 2 3\nf 1/1 3/2 4/1\nf 1//1 2//1 4//1\n"
          "f 2/2/1 3/1/1 4/2/1\nl 1 2\np 3\n")
    write("obj", "relative.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nf -5 -4 -3 -2 -1\nv 2 2 2\nf -1 1 2\n")
    write("obj", "crlf_tabs.obj", "v\t0 0 0\r\nv 1 0 0\r\n  v 0 1 0 # comment\r\nf\t1 2 3\r\n")
    write("obj", "numbers.obj",
          "v 1e-320 -0 .5\nv 5. +1.5e+3 0.30000000000000004\nv 1.7976931348623157e308 2.2250738585072014e-308 "
          "123456789012345678901234567890\nv 0.1234567890123456789e-40 9007199254740993 -2.5E-3\nf 1 2 3 4\n")
    write("obj", "uv_pairing.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nvt 0.125 0.25\nvt 0.5 0.75\nf 1/1 2/2 3/3\n"
                                   "f 1/2 3/1 2/1\nvt 0.875 1\n")
    pts, tris = grid(4, 3)
    text = "# written by cloth.h 0.1.0\n" + "".join("v %r %r %r\n" % p for p in pts)
    text += "".join("vt %r %r\n" % (p[0] + 0.3, p[2]) for p in pts)
    text += "".join("f %d/%d %d/%d %d/%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in tris)
    write("obj", "grid_uv.obj", text)
    write("obj", "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
    write("obj", "bad_number.obj", "v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n")
    write("obj", "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n")
    write("obj", "unknown_statement.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvertex 1 2 3\nf 1 2 3\n")
    write("obj", "two_corners.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n")
    write("obj", "vt_out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n")
    write("obj", "empty.obj", "# nothing\n")


# ---- PLY --------------------------------------------------------------------------------

PLY_FORMATS = {"<": "binary_little_endian", ">": "binary_big_endian"}


def ply_binary(order, vertex_props, vertices, face_count_type="B", face_index_type="i", faces=(), extra_header="",
               extra_body=b"", uv=False):
    names = {"b": "char", "B": "uchar", "h": "short", "H": "ushort", "i": "int", "I": "uint", "f": "float", "d": "double"}
    head = "ply\nformat %s 1.0\ncomment seed\n" % PLY_FORMATS[order]
    head += extra_header
    head += "element vertex %d\n" % len(vertices)
    for t, n in vertex_props:
        head += "property %s %s\n" % (names[t], n)
    head += "element face %d\nproperty list %s %s vertex_indices\nend_header\n" % (
        len(faces), names[face_count_type], names[face_index_type])
    body = extra_body
    for v in vertices:
        body += b"".join(struct.pack(order + t, x) for (t, _), x in zip(vertex_props, v))
    for f in faces:
        body += struct.pack(order + face_count_type, len(f)) + b"".join(struct.pack(order + face_index_type, i) for i in f)
    return head.encode("ascii") + body


def ply_corpus():
    write("ply", "ascii_triangle.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                       "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write("ply", "ascii_extras.ply",
          "ply\r\nformat ascii 1.0\r\ncomment unknown elements and lists\nobj_info x\nelement material 2\n"
          "property list uchar float shininess\nproperty int id\nelement vertex 5\nproperty float temperature\n"
          "property double x\nproperty list int int neighbours\nproperty double y\nproperty float s\nproperty double z\n"
          "property float t\nelement face 2\nproperty uchar flags\nproperty list int uint vertex_index\n"
          "property list uchar float weights\nend_header\n2 0.5 0.25 7\n0 9\n20.5 0 2 1 2 0 0.125 0 0.75\n"
          "21 1 0 0 0.25 0 0.5\n22 1 1 4 1 0.375 0 1\n23 0.5 0 1.5 0.5 -1e-3 1\n24 0 0 1 1 2.5e2 1\n"
          "7 3 0 1 2 3 0.1 0.2 0.3\n0 4 0 2 3 4 0\n")
    write("ply", "ascii_texture_uv.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "property float texture_u\nproperty float texture_v\nelement face 1\nproperty list uchar int vertex_indices\n"
          "end_header\n0 0 0 0.5 0.25\n1 0 0 1 0.25\n0 1 0 0.5 1\n3 0 1 2\n")
    pts, tris = grid(4, 3)
    xyz_f = [("f", "x"), ("f", "y"), ("f", "z")]
    write("ply", "le_float.ply", ply_binary("<", xyz_f, pts, faces=tris))
    xyz_uv_d = [("d", "x"), ("d", "y"), ("d", "z"), ("d", "u"), ("d", "v")]
    write("ply", "be_double_uv.ply", ply_binary(">", xyz_uv_d, [p + (p[0] + 0.3, p[2]) for p in pts], "I", "H", tris))
    ints = [("b", "x"), ("h", "y"), ("H", "z"), ("i", "extra")]
    write("ply", "le_integer_coordinates.ply",
          ply_binary("<", ints, [(0, 0, 0, 7), (2, 0, 1, 7), (2, -3, 1, 7), (0, 3, 100, 7)], "H", "I",
                     [(0, 1, 2, 3), (3, 2, 1)]))
    write("ply", "be_polygons.ply", ply_binary(">", xyz_f, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 1.5, 0)], "B",
                                               "i", [(0, 1, 2, 3, 4), (4, 3, 2)]))
    write("ply", "le_unknown_element.ply",
          ply_binary("<", xyz_f, pts[:4], faces=[(0, 1, 2), (0, 2, 3)],
                     extra_header="element edge 2\nproperty int a\nproperty list ushort double w\n",
                     extra_body=struct.pack("<iHd", 1, 1, 0.5) + struct.pack("<iHdd", 2, 2, 0.25, 0.75)))
    write("ply", "bad_version.ply", "ply\nformat ascii 2.0\nelement vertex 0\nend_header\n")
    full = ply_binary("<", xyz_f, pts, faces=tris)
    write("ply", "truncated_le.ply", full[:-7])
    write("ply", "huge_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2147483647\nproperty float x\n"
                                   "property float y\nproperty float z\nend_header\n0000000000000")
    write("ply", "index_out_of_range.ply", ply_binary("<", xyz_f, pts[:3], faces=[(0, 1, 3)]))
    write("ply", "nan.ply", ply_binary(">", xyz_f, [(0, 0, 0), (1, float("nan"), 0), (0, 1, 0)], faces=[(0, 1, 2)]))
    write("ply", "no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n")


# ---- VTK --------------------------------------------------------------------------------

def vtk_file(binary, v51, points, cells, types, point_type="double", before_points="", after="", polydata=False):
    out = [b"# vtk DataFile Version %s\nseed\n%s\nDATASET %s\n" % (
        b"5.1" if v51 else b"4.2", b"BINARY" if binary else b"ASCII", b"POLYDATA" if polydata else b"UNSTRUCTURED_GRID")]
    out.append(before_points.encode("ascii") if isinstance(before_points, str) else before_points)
    out.append(b"POINTS %d %s\n" % (len(points), point_type.encode("ascii")))
    code = {"double": ">d", "float": ">f", "int": ">i"}[point_type]
    flat = [c for p in points for c in p]
    if binary:
        out.append(b"".join(struct.pack(code, c) for c in flat) + b"\n")
    else:
        out.append((" ".join(repr(c) if point_type != "int" else str(int(c)) for c in flat) + "\n").encode("ascii"))
    keyword = b"POLYGONS" if polydata else b"CELLS"
    if v51:
        offsets = [0]
        for c in cells:
            offsets.append(offsets[-1] + len(c))
        conn = [i for c in cells for i in c]
        out.append(b"%s %d %d\nOFFSETS vtktypeint64\n" % (keyword, len(offsets), len(conn)))
        out.append(b"".join(struct.pack(">q", o) for o in offsets) + b"\n" if binary else
                   (" ".join(map(str, offsets)) + "\n").encode("ascii"))
        out.append(b"CONNECTIVITY vtktypeint64\n")
        out.append(b"".join(struct.pack(">q", i) for i in conn) + b"\n" if binary else
                   (" ".join(map(str, conn)) + "\n").encode("ascii"))
    else:
        size = sum(len(c) + 1 for c in cells)
        out.append(b"%s %d %d\n" % (keyword, len(cells), size))
        for c in cells:
            out.append(b"".join(struct.pack(">i", v) for v in (len(c),) + tuple(c)) if binary else
                       (" ".join(map(str, (len(c),) + tuple(c))) + "\n").encode("ascii"))
        if binary:
            out.append(b"\n")
    if not polydata:
        out.append(b"CELL_TYPES %d\n" % len(types))
        out.append(b"".join(struct.pack(">i", t) for t in types) + b"\n" if binary else
                   ("\n".join(map(str, types)) + "\n").encode("ascii"))
    out.append(after.encode("ascii") if isinstance(after, str) else after)
    return b"".join(out)


def vtk_corpus():
    pts, tris = grid(4, 3)
    types = [5] * len(tris)
    for binary in (0, 1):
        for v51 in (0, 1):
            write("vtk", "grid_%s_%s.vtk" % ("v51" if v51 else "v42", "binary" if binary else "ascii"),
                  vtk_file(binary, v51, pts, tris, types))
    mixed_pts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 1.5, 0.25), (0.5, 0.5, 1)]
    mixed_cells = [(0, 1, 2), (0, 1, 2, 3), (0, 5), (5,), (0, 1, 2, 4, 3), (0, 1, 2, 5)]
    mixed_types = [5, 9, 3, 1, 7, 10]
    write("vtk", "mixed_cells_ascii.vtk", vtk_file(0, 0, mixed_pts, mixed_cells, mixed_types))
    write("vtk", "mixed_cells_binary_v51.vtk", vtk_file(1, 1, mixed_pts, mixed_cells, mixed_types))
    write("vtk", "field_and_metadata.vtk",
          vtk_file(0, 1, mixed_pts, mixed_cells, mixed_types,
                   before_points="FIELD FieldData 2\nTIME 1 1 double\n1.25\nCYCLE 1 1 int\n3\n",
                   after="POINT_DATA 6\nSCALARS t float 1\nLOOKUP_TABLE default\n1 2 3 4 5 6\n"
                         "CELL_DATA 6\nFIELD FieldData 1\nmaterial 1 6 int\n0 1 2 3 0 1\n"))
    write("vtk", "attributes_binary.vtk",
          vtk_file(1, 0, pts, tris, types, point_type="float",
                   before_points=b"FIELD FieldData 1\nTIME 1 1 double\n" + struct.pack(">d", 2.5) + b"\n",
                   after=b"POINT_DATA 12\nFIELD FieldData 1\ntemperature 1 12 float\n" +
                         b"".join(struct.pack(">f", 20 + k) for k in range(12)) + b"\n"))
    write("vtk", "polydata.vtk",
          b"# vtk DataFile Version 3.0\npolydata\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n0 0 0 1 0 0 1 1 0\n"
          b"0 1 0 0.5 0.5 0.5\nVERTICES 1 2\n1 4\nLINES 1 3\n2 0 4\nPOLYGONS 2 9\n4 0 1 2 3\n3 1 2 4\n")
    write("vtk", "int_points.vtk", vtk_file(0, 0, [(0, 0, 0), (2, 0, 0), (0, 2, 0)], [(0, 1, 2)], [5], point_type="int"))
    write("vtk", "structured_points.vtk",
          "# vtk DataFile Version 2.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n")
    write("vtk", "no_cell_types.vtk",
          "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
          "CELLS 1 4\n3 0 1 2\n")
    write("vtk", "huge_points.vtk",
          "# vtk DataFile Version 2.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 2147483647 double\n00000000")
    write("vtk", "index_out_of_range_binary.vtk", vtk_file(1, 0, pts[:3], [(0, 1, 3)], [5]))
    write("vtk", "nan_ascii.vtk",
          "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 nan 0 0 1 0\n"
          "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n")


# ---- OFF --------------------------------------------------------------------------------

def off_corpus():
    write("off", "triangle.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write("off", "counts_on_header.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write("off", "comments.off", "OFF\n# Created by hand\n\n4 2 0\n\n0 0 0\n1 0 0 # comment\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n")
    write("off", "colours.off", "COFF\n3 1 3\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2 1 0 0\n")
    write("off", "polygons.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n5 0 1 2 3 4\n3 4 3 2\n")
    write("off", "crlf.off", "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n")
    pts, tris = grid(4, 3)
    text = "OFF\n%d %d 0\n" % (len(pts), len(tris)) + "".join("%r %r %r\n" % p for p in pts)
    text += "".join("3 %d %d %d\n" % t for t in tris)
    write("off", "grid.off", text)
    write("off", "normals.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
    write("off", "truncated.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    write("off", "index_out_of_range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")
    write("off", "nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n")
    write("off", "four_dimensional.off", "4OFF\n3 1 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n")
    write("off", "huge_count.off", "OFF\n2147483647 1 0\n0 0 0\n")
    # found by fuzz_off: a face count of 2^31 - 1 on a short line once sized the triangle array
    write("off", "regression_huge_face_count.off", base64.b64decode(
        "Tk9GRgozIDEgMAoAAAAAAAAAgAAAAAAAAAAAAAAAAAAAAAAAAAAAADAgMCAwIDAgMCAxCjEgMCAwIDAgMCAxCjBGRgoyMTQ3NDgzNjQ3"
        "ICAxIDAgMCAwIDEKMyAwIDEgMgo="))


if __name__ == "__main__":
    obj_corpus()
    ply_corpus()
    vtk_corpus()
    off_corpus()
    for kind in ("obj", "ply", "vtk", "off"):
        print("fuzz/corpus/%s: %d files" % (kind, len(os.listdir(os.path.join(HERE, "corpus", kind)))))
