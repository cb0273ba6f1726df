"""Python threads on one hpfc.File: the array calls run in C without the GIL
(so threads overlap), give every thread the answers of one thread alone,
and close() refuses while one runs."""

import sys
import threading

import numpy as np

import hpfc
from test_locate import domain_points


def test_eight_threads_same_answers(delaunay, counties):
    for path in (delaunay, counties):
        with hpfc.open(path) as f:
            queries = []
            for seed in range(6):
                xs, ys = domain_points(f, 5000 + 1000 * seed, seed=100 + seed)
                queries.append((xs, ys))
            lattice = [(np.floor(x / 10.0 ** f.info["unit_exp10"]).astype(np.int64),
                        np.floor(y / 10.0 ** f.info["unit_exp10"]).astype(np.int64))
                       for x, y in queries]

            def answer(q):
                if q < len(queries):
                    b = f.locate(*queries[q])
                else:
                    b = f.locate_lattice(*lattice[q - len(queries)])
                return (b.face.copy(), b.face_count.copy(), b.feature.copy(),
                        b.feature_count.copy(), b.flags.copy())

            n = 2 * len(queries)
            want = [answer(q) for q in range(n)]
            errors = []
            start = threading.Barrier(8)

            def work(k):
                start.wait()
                rng = np.random.default_rng(k)
                for _ in range(3):
                    for q in rng.permutation(n):
                        got = answer(int(q))
                        if not all(np.array_equal(a, b) for a, b in zip(got, want[q])):
                            errors.append((k, int(q)))

            threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            assert errors == []


def test_the_gil_is_released_during_a_batch(delaunay):
    """With a switch interval far beyond the test, the main thread runs
    while the worker is inside locate() only if the call released the GIL;
    it then finds the file busy (the worker gives back its count only once
    it holds the GIL again), so close() must refuse."""
    old = sys.getswitchinterval()
    with hpfc.open(delaunay) as f:
        xs, ys = domain_points(f, 400000, seed=3)
        entering = threading.Event()
        result = {}

        def work():
            entering.set()
            result["faces"] = f.locate(xs, ys).face

        sys.setswitchinterval(1000.0)
        try:
            t = threading.Thread(target=work)
            t.start()
            entering.wait()
            try:
                f.close()
                refused = False
            except RuntimeError as e:
                refused = "in use" in str(e)
        finally:
            sys.setswitchinterval(old)
        t.join()
        assert refused, "the main thread ran only once locate() was over: GIL held"
        assert len(result["faces"]) == len(xs)
