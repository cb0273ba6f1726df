// test_cpp_header.cc: hpfc.h and hpfc_batch.h as a C++ program sees them.
// tests/meson.build compiles this file as C++11 with -Wall -Wextra
// -Wpedantic -Werror, once as is and once with HPFC_EXPERIMENTAL, and
// links it against the shared library: the headers must compile as C++
// (extern "C", no C-only syntax), and the calls below must link, the
// experimental tier's too (exported like every other call).
#include <cstdio>
#include <cstring>

#include "hpfc.h"
#include "hpfc_batch.h"

static int failures = 0;

static void check(bool ok, const char *what)
{
    if (!ok) {
        std::fprintf(stderr, "check failed: %s\n", what);
        failures++;
    }
}

int main()
{
    check(std::strcmp(hpfc_status_name(HPFC_E_CORRUPT), "HPFC_E_CORRUPT") == 0, "status name");
    check(hpfc_strerror(HPFC_E_ARG) != nullptr, "strerror");
    check(hpfc_version_number() == HPFC_VERSION_NUMBER, "version");
    check(HPFC_ID_NONE == UINT64_MAX && sizeof(hpfc_id) == 8, "ids");

    // a square: four vertices, four edges, two faces
    hpfc_graph *g = nullptr;
    check(hpfc_graph_create(&g) == HPFC_OK, "graph");
    const int64_t xy[8] = {0, 0, 8, 0, 8, 8, 0, 8};
    for (int k = 0; k < 4; k++)
        hpfc_graph_add_vertex(g, xy[2 * k], xy[2 * k + 1], nullptr);
    for (uint32_t k = 0; k < 4; k++)
        hpfc_graph_add_edge(g, k, (k + 1) % 4, nullptr, 0, nullptr);
    hpfc_build_params p;
    hpfc_build_params_default(&p);
    hpfc_tree *t = nullptr;
    hpfc_diag diag;
    check(hpfc_build(g, &p, &t, &diag) == HPFC_OK, "build");
    hpfc_write_options o;
    std::memset(&o, 0, sizeof o);
    o.face_labels = 1;
    o.geometry = g;
    uint8_t *buf = nullptr;
    size_t size = 0;
    check(hpfc_tree_serialize(t, &o, &buf, &size, &diag) == HPFC_OK, "serialize");

    hpfc_file *f = nullptr;
    check(hpfc_open_memory(buf, size, 0, &f) == HPFC_OK, "open");
    if (f) {
        check(hpfc_file_check_checksums(f, &diag) == HPFC_OK, "checksums");
        hpfc_geometry_info gi;
        check(hpfc_file_get_geometry(f, &gi) == HPFC_OK && gi.vertices == 4, "geometry");
        hpfc_point_location loc;
        hpfc_id faces[4];
        size_t n = 0;
        check(hpfc_locate_point(f, 4, 4, &loc, faces, 4, &n) == HPFC_OK && n == 1 &&
                  loc.vertex == HPFC_ID_NONE,
              "locate");
        const int64_t x[1] = {4}, y[1] = {4};
        int64_t face[1] = {0};
        hpfc_locate_out out;
        std::memset(&out, 0, sizeof out);
        out.face = face;
        check(hpfc_locate_batch(f, nullptr, 1, x, y, nullptr, &out, nullptr) == HPFC_OK &&
                  face[0] == static_cast<int64_t>(faces[0]),
              "batch");
        hpfc_walker *w = nullptr;
        check(hpfc_walker_create(f, &w) == HPFC_OK, "walker");
        hpfc_pixel px;
        uint64_t key = HPFC_KEY_INVALID;
        check(hpfc_locate(f, 0, 0, &px) == HPFC_OK &&
                  hpfc_pixel_vertex_key(w, &px, 0, &key) == HPFC_OK,
              "vertex key");
#ifdef HPFC_EXPERIMENTAL
        hpfc_vertex v;
        check(hpfc_vertex_from_key(w, key, &v) == HPFC_OK && hpfc_vertex_key(f, &v) == key,
              "path form");
        check(hpfc_walker_pixels_visited(w) > 0, "pixels visited");
#endif
        hpfc_walker_free(w);
        hpfc_close(f);
    }
    hpfc_free(buf);
    hpfc_tree_free(t);
    hpfc_graph_free(g);
    std::printf("cpp_header: %d failed\n", failures);
    return failures ? 1 : 0;
}
