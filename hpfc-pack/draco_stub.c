/*
 * draco_input.h for builds without Draco: .drc input is refused with one
 * clear reason (hpfc-pack treats it as an unsupported input format).
 */
#include <stdio.h>
#include <string.h>

#include "draco_input.h"

static int not_built(hpfc_graph **out, hpfc_diag *diag)
{
    if (out)
        *out = NULL;
    if (diag) {
        memset(diag, 0, sizeof *diag);
        diag->status = DRACO_E_NOT_BUILT;
        diag->edge[0] = diag->edge[1] = -1;
        snprintf(diag->message, sizeof diag->message,
                 ".drc input needs Draco, not built in (install libdraco-dev and rebuild)");
    }
    return DRACO_E_NOT_BUILT;
}

int draco_input_available(void)
{
    return 0;
}

int draco_graph_from_memory(const void *data, size_t size, const draco_options *opts,
                            hpfc_graph **out, hpfc_diag *diag)
{
    (void)data, (void)size, (void)opts;
    return not_built(out, diag);
}

int draco_read_graph(const char *path, const draco_options *opts, hpfc_graph **out,
                     hpfc_diag *diag)
{
    (void)path, (void)opts;
    return not_built(out, diag);
}
