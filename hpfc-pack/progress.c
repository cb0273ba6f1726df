/* The progress bar of hpfc-pack (progress.h). */
#include "progress.h"

#include <stdio.h>
#include <time.h>

#include "clock.h"

void progress_show(progress *p, const char *stage, double done, double total, int force)
{
    if (!p->on)
        return;
    double t = clock_seconds();
    if (!force && t - p->last < 0.1)
        return;
    p->last = t;
    if (total > 0) {
        double r = done / total;
        r = r < 0 ? 0 : r > 1 ? 1 : r;
        char bar[31];
        int n = (int)(r * 30);
        for (int i = 0; i < 30; i++)
            bar[i] = i < n ? '#' : '.';
        bar[30] = 0;
        fprintf(stderr, "\rhpfc-pack: %-10s [%s] %3d%%\033[K", stage, bar, (int)(r * 100));
    } else
        fprintf(stderr, "\rhpfc-pack: %-10s ...\033[K", stage);
    fflush(stderr);
    p->drawn = 1;
}

void progress_end(progress *p)
{
    if (p->on && p->drawn) {
        fprintf(stderr, "\r\033[K");
        fflush(stderr);
        p->drawn = 0;
    }
}
