"""Triangle meshes from files, NumPy only: STL (binary, ASCII), OBJ, OFF, PLY (ASCII, binary) and GLB.

`read_mesh_file(path) -> (vertices (V, 3) [file units], faces (F, 3) int)`: polygons are split
into fans of triangles, and vertices with equal coordinates are merged (STL repeats them per
face), so that a closed surface comes back closed for `physics.inertia.mesh_mass_properties`.
GLB: every triangle primitive of every mesh node, with the nodes' transforms.  Anything else, or
a file these readers cannot parse, raises `physics.inertia.MeshError` naming the file.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from physics.inertia import MeshError

__all__ = ["MESH_SUFFIXES", "read_mesh_bytes", "read_mesh_file"]

MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb")

Mesh = tuple[NDArray[np.float64], NDArray[np.int64]]


def _fans(polygons: list[list[int]]) -> NDArray[np.int64]:
    """Polygons (vertex indices) split into triangles (k, 0, k+1 ... as fans)."""
    triangles = [(p[0], p[k], p[k + 1]) for p in polygons for k in range(1, len(p) - 1)]
    return np.array(triangles, dtype=np.int64).reshape(-1, 3)


def _stl(data: bytes) -> Mesh:
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if len(data) == 84 + 50 * count:
            records = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                    count=count, offset=84)
            corners = records["v"].astype(float).reshape(-1, 3)
            return corners, np.arange(3 * count, dtype=np.int64).reshape(-1, 3)
    words = data.decode("ascii", errors="strict").split()
    corners_list = [[float(w) for w in words[k + 1:k + 4]] for k, w in enumerate(words) if w == "vertex"]
    if not corners_list or len(corners_list) % 3:
        raise ValueError("no facets")
    corners = np.array(corners_list)
    return corners, np.arange(len(corners), dtype=np.int64).reshape(-1, 3)


def _obj(data: bytes) -> Mesh:
    vertices: list[list[float]] = []
    polygons: list[list[int]] = []
    for line in data.decode("utf-8").splitlines():
        parts = line.split()
        if parts[:1] == ["v"]:
            vertices.append([float(x) for x in parts[1:4]])
        elif parts[:1] == ["f"]:
            indices = [int(p.split("/")[0]) for p in parts[1:]]
            polygons.append([i - 1 if i > 0 else len(vertices) + i for i in indices])
    return np.array(vertices, dtype=float).reshape(-1, 3), _fans(polygons)


def _off(data: bytes) -> Mesh:
    lines = [line.split("#")[0].split() for line in data.decode("utf-8").splitlines()]
    words = [w for line in lines for w in line]
    if not words or not words[0].endswith("OFF"):
        raise ValueError("no OFF header")
    n_vertices, n_faces = int(words[1]), int(words[2])
    at = 4
    vertices = np.array(words[at:at + 3 * n_vertices], dtype=float).reshape(n_vertices, 3)
    at += 3 * n_vertices
    polygons = []
    for _ in range(n_faces):
        n = int(words[at])
        polygons.append([int(w) for w in words[at + 1:at + 1 + n]])
        at += 1 + n
    return vertices, _fans(polygons)


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def _ply(data: bytes) -> Mesh:
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt = ""
    elements: list[tuple[str, int, list[list[str]]]] = []
    for line in header:
        parts = line.split()
        if parts[:1] == ["format"]:
            fmt = parts[1]
        elif parts[:1] == ["element"]:
            elements.append((parts[1], int(parts[2]), []))
        elif parts[:1] == ["property"]:
            elements[-1][2].append(parts[1:])
    body = data[end:]
    vertices = np.zeros((0, 3))
    polygons: list[list[int]] = []
    if fmt == "ascii":
        words = body.split()
        at = 0
        for name, count, properties in elements:
            for _ in range(count):
                row: dict[str, Any] = {}
                for prop in properties:
                    if prop[0] == "list":
                        n = int(words[at])
                        row[prop[3]] = [int(w) for w in words[at + 1:at + 1 + n]]
                        at += 1 + n
                    else:
                        row[prop[1]] = float(words[at])
                        at += 1
                if name == "vertex":
                    vertices = np.vstack([vertices, [[row["x"], row["y"], row["z"]]]])
                elif name == "face":
                    polygons.append(row.get("vertex_indices", row.get("vertex_index", [])))
        return vertices, _fans(polygons)
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(fmt)
    if order is None:
        raise ValueError(f"PLY format {fmt!r}")
    at = 0
    for name, count, properties in elements:
        if all(prop[0] != "list" for prop in properties):
            dtype = np.dtype([(prop[1], order + _PLY_TYPES[prop[0]]) for prop in properties])
            rows = np.frombuffer(body, dtype=dtype, count=count, offset=at)
            at += dtype.itemsize * count
            if name == "vertex":
                vertices = np.column_stack([rows["x"], rows["y"], rows["z"]]).astype(float)
            continue
        for _ in range(count):
            row = {}
            for prop in properties:
                if prop[0] == "list":
                    count_type = np.dtype(order + _PLY_TYPES[prop[1]])
                    index_type = np.dtype(order + _PLY_TYPES[prop[2]])
                    n = int(np.frombuffer(body, count_type, 1, at)[0])
                    at += count_type.itemsize
                    row[prop[3]] = np.frombuffer(body, index_type, n, at).astype(int).tolist()
                    at += index_type.itemsize * n
                else:
                    at += np.dtype(_PLY_TYPES[prop[0]]).itemsize
            if name == "face":
                polygons.append(row.get("vertex_indices", row.get("vertex_index", [])))
    return vertices, _fans(polygons)


_GLB_COMPONENTS = {5120: "i1", 5121: "u1", 5122: "i2", 5123: "u2", 5125: "u4", 5126: "f4"}
_GLB_SIZES = {"SCALAR": 1, "VEC3": 3}


def _node_matrix(node: dict[str, Any]) -> NDArray[np.float64]:
    if "matrix" in node:
        return np.array(node["matrix"], dtype=float).reshape(4, 4).T  # column-major in glTF
    x, y, z, w = node.get("rotation", (0.0, 0.0, 0.0, 1.0))
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    M = np.eye(4)
    M[:3, :3] = R * np.asarray(node.get("scale", (1.0, 1.0, 1.0)), dtype=float)
    M[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return M


def _glb(data: bytes) -> Mesh:
    magic, _version, _length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF":
        raise ValueError("no glTF header")
    json_length, _ = struct.unpack_from("<II", data, 12)
    gltf = json.loads(data[20:20 + json_length])
    at = 20 + json_length
    bin_length, _ = struct.unpack_from("<II", data, at)
    binary = data[at + 8:at + 8 + bin_length]

    def accessor(index: int) -> NDArray[Any]:
        acc = gltf["accessors"][index]
        view = gltf["bufferViews"][acc["bufferView"]]
        dtype = np.dtype("<" + _GLB_COMPONENTS[acc["componentType"]])
        width = _GLB_SIZES[acc["type"]]
        offset = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
        stride = view.get("byteStride", dtype.itemsize * width)
        rows = np.lib.stride_tricks.as_strided(
            np.frombuffer(binary, dtype=np.uint8, offset=offset), shape=(acc["count"], width * dtype.itemsize),
            strides=(stride, 1))
        return np.frombuffer(rows.tobytes(), dtype=dtype).reshape(acc["count"], width)

    vertices: list[NDArray[np.float64]] = []
    faces: list[NDArray[np.int64]] = []
    count = 0

    def visit(index: int, parent: NDArray[np.float64]) -> None:
        nonlocal count
        node = gltf["nodes"][index]
        M = parent @ _node_matrix(node)
        for primitive in gltf["meshes"][node["mesh"]]["primitives"] if "mesh" in node else []:
            if primitive.get("mode", 4) != 4:
                continue
            points = accessor(primitive["attributes"]["POSITION"]).astype(float)
            if "indices" in primitive:
                triangles = accessor(primitive["indices"]).astype(np.int64).reshape(-1, 3)
            else:
                triangles = np.arange(len(points), dtype=np.int64).reshape(-1, 3)
            vertices.append(points @ M[:3, :3].T + M[:3, 3])
            faces.append(triangles + count)
            count += len(points)
        for child in node.get("children", []):
            visit(child, M)

    scene = gltf["scenes"][gltf.get("scene", 0)]
    for root in scene["nodes"]:
        visit(root, np.eye(4))
    if not vertices:
        raise ValueError("no triangles")
    return np.vstack(vertices), np.vstack(faces)


_READERS = {".stl": _stl, ".obj": _obj, ".off": _off, ".ply": _ply, ".glb": _glb}


def read_mesh_bytes(name: str, data: bytes) -> Mesh:
    """(vertices (V, 3), faces (F, 3)) of a mesh file's bytes, its kind from the suffix of
    `name`, equal vertices merged; MeshError naming `name` if the kind is not one of
    MESH_SUFFIXES or the bytes cannot be parsed as one."""
    reader = _READERS.get(Path(name).suffix.lower())
    if reader is None:
        raise MeshError(f"{name}: a mesh ({', '.join(MESH_SUFFIXES)}) wanted")
    try:
        vertices, faces = reader(data)
    except UnicodeDecodeError:  # said in plain words: a text format holding binary bytes
        kind = Path(name).suffix.lstrip(".").upper()
        raise MeshError(f"{name}: not a readable mesh (this {kind} file holds binary bytes where {kind} has "
                        f"text: export it as a text {kind}, or as STL, PLY or GLB)") from None
    except (ValueError, IndexError, KeyError, TypeError, struct.error) as error:
        raise MeshError(f"{name}: not a readable mesh ({type(error).__name__}: {error})") from None
    if faces.size == 0 or len(vertices) == 0:
        raise MeshError(f"{name}: not a readable mesh (no triangles)")
    if faces.min() < 0 or faces.max() >= len(vertices) or not np.all(np.isfinite(vertices)):
        raise MeshError(f"{name}: not a readable mesh (bad vertex indices or coordinates)")
    unique, inverse = np.unique(vertices, axis=0, return_inverse=True)
    return unique, inverse.reshape(-1)[faces]


def read_mesh_file(path: Path) -> Mesh:
    """`read_mesh_bytes` of a file (MeshError naming the path)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        raise MeshError(f"{path}: not a readable mesh ({type(error).__name__}: {error})") from None
    return read_mesh_bytes(str(path), data)
