"""Traversal against the input graph: vertices, darts and faces of a packed
.pfc file counted and walked, leaves and pixels against the level table."""

import collections

import pytest

import hpfc
from conftest import DATA


def read_pfc(path):
    """(vertex count, edge list, loops) of a .pfc file: the independent oracle."""
    nv, edges = 0, []
    for line in open(path):
        fields = line.split("#")[0].split()
        if not fields:
            continue
        if fields[0] == "v":
            nv += 1
        elif fields[0] == "e":
            edges.append((int(fields[1]), int(fields[2])))
    return nv, edges


def components(nv, edges):
    parent = list(range(nv))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for u, v in edges:
        parent[find(u)] = find(v)
    return len({find(a) for a in range(nv)})


SOURCES = {"delaunay": "delaunay-4000.pfc", "polyline": "polyline-3000.pfc"}


@pytest.mark.parametrize("name", sorted(SOURCES))
def test_map_matches_input_graph(request, name):
    path = request.getfixturevalue(name)
    nv, edges = read_pfc(DATA / SOURCES[name])
    with hpfc.open(path) as f:
        vertices = list(f.vertices())
        assert len(vertices) == nv and len(set(vertices)) == nv
        darts = list(f.darts())
        assert len(darts) == 2 * len(edges) and len(set(darts)) == len(darts)
        dart_set = set(darts)
        degree = collections.Counter()
        for u, v in edges:
            degree[u] += 1
            degree[v] += 1
        assert sorted(len(f.vertex_darts(v)) for v in vertices) == sorted(
            degree[k] for k in range(nv))
        # Euler: V - E + F = 1 + C
        c = components(nv, edges)
        assert f.face_count == 1 + c - nv + len(edges)
        faces = set()
        for d in darts:
            t, n, p = f.twin(d), f.next(d), f.prev(d)
            assert t in dart_set and n in dart_set and p in dart_set
            assert t != d and f.twin(t) == d
            assert f.prev(n) == d and f.next(p) == d
            assert f.origin(t) == f.target(d) and f.target(t) == f.origin(d)
            assert f.origin(n) == f.target(d)
            assert d in f.vertex_darts(f.origin(d))
            face = f.dart_face(d)
            assert face == f.dart_face(n)
            faces.add(face)
        assert faces == set(range(f.face_count))
        # boundary loops partition the darts
        seen = set()
        loops = 0
        for d in darts:
            if d in seen:
                continue
            loop = list(f.face_boundary(d))
            assert not seen.intersection(loop)
            assert len({f.dart_face(x) for x in loop}) == 1
            seen.update(loop)
            loops += 1
        assert seen == dart_set
        # a face with holes has one loop a boundary component: loops = F - 1 + C
        assert loops == f.face_count - 1 + c
        # dense indices are distinct and below their bound
        bound_d, bound_v = f.key_index_bound()
        idx = {f.dart_index(d) for d in darts}
        assert len(idx) == len(darts) and max(idx) < bound_d
        vidx = {f.vertex_index(v) for v in vertices}
        assert len(vidx) == nv and max(vidx) < bound_v
        # a dart's pixel holds its origin vertex
        for d in darts[:200]:
            assert f.dart_pixel(d) == f.vertex_pixel(f.origin(d))
            assert f.origin(d) in f.dart_pixel(d).vertex_keys()


def test_leaves_and_pixels_match_level_table(delaunay):
    with hpfc.open(delaunay) as f:
        levels = f.levels
        leaves = list(f.leaves())
        assert len(leaves) == sum(l["word_pixels"] for l in levels)
        assert all(px.kind == "word" for px in leaves)
        assert len(set(leaves)) == len(leaves)
        per_depth = collections.Counter(px.depth for px in leaves)
        assert [per_depth[l] for l in range(len(levels))] == [l["word_pixels"] for l in levels]
        pixels = list(f.pixels())
        assert len(pixels) == sum(l["word_pixels"] + l["refined_pixels"] for l in levels)
        assert [px for px in pixels if px.kind == "word"] == leaves  # same depth-first order
        private = [px for px in leaves if px.is_private]
        assert all(px.word == "++++" for px in private)
        assert all(len(px.faces()) == 1 for px in private[:100])


def test_pixel_navigation(delaunay):
    with hpfc.open(delaunay) as f:
        info = f.info
        root = f.root(0, 0)
        assert root.depth == 0 and root.parent is None and root.path == ((0, 0),)
        assert str(root) == "0,0"
        assert root.move(hpfc.WEST) is None and root.move(hpfc.NORTH) is None
        east = root.move(hpfc.EAST)
        assert east is not None and east.path[0][0] >= 1 and east.move(hpfc.WEST) is not None
        refined = next(px for px in f.pixels() if px.kind == "refined")
        child = refined.child(1, 0)
        assert child.parent == refined and child.depth == refined.depth + 1
        x0, y0, x1, y1 = refined.bounds
        cx0, cy0, cx1, cy1 = child.bounds
        assert x0 <= cx0 < cx1 <= x1 and y0 <= cy0 < cy1 <= y1
        with pytest.raises(hpfc.Error):
            refined.word  # a refined pixel has no word
        with pytest.raises(hpfc.Error):
            f.root(info["root_cols"], 0)
        with pytest.raises(ValueError):
            root.move(7)
        # leaf_at agrees with a leaf's own bounds
        leaf = next(px for px in f.leaves() if px.depth >= 2)
        bx0, by0, bx1, by1 = leaf.bounds
        assert f.leaf_at(bx0, by0) == leaf and f.leaf_at(bx1 - 1, by1 - 1) == leaf
        assert hash(f.leaf_at(bx0, by0)) == hash(leaf)


def test_bad_keys_raise(delaunay):
    with hpfc.open(delaunay) as f:
        dart = next(iter(f.darts()))
        for bad in (dart + 1_000_000_007, 2**64 - 1, 1):
            with pytest.raises(hpfc.Error) as e:
                f.next(bad)
            assert e.value.name == "HPFC_E_ARG" and e.value.code == 2
        with pytest.raises(OverflowError):
            f.twin(-1)
        with pytest.raises(TypeError):
            f.twin("dart")
