/*
 * open_input.h: how every mode of hpfc-inspect reads FILE. "-" is standard
 * input; a regular file is mapped, and what cannot be mapped (a pipe, a
 * FIFO, a terminal) is read to its end into memory. A pipe can be read
 * once only, so a mode reads FILE once, through one of these, and never by
 * name again.
 */
#ifndef HPFC_INSPECT_OPEN_INPUT_H
#define HPFC_INSPECT_OPEN_INPUT_H

#include <stddef.h>
#include <stdint.h>

#include "hpfc.h"

/* FILE's bytes, for code that reads what no API exposes (--verify's
 * padding checks) and opens them with hpfc_open_memory. */
typedef struct input_bytes {
    const uint8_t *data;
    size_t size;
    void *map;      /* the mapping, or NULL */
    uint8_t *owned; /* the bytes read, or NULL */
} input_bytes;

/* FILE as a path the system resolves: "/dev/stdin" for "-". What a
 * same_file() check against an output must compare. */
const char *input_path(const char *file);

/* FILE opened as hpfc_open does, read into memory (HPFC_OPEN_READ) when it
 * cannot be mapped. An hpfc status; errno says why after HPFC_E_IO. */
int open_input(const char *file, hpfc_file **f);

/* FILE's bytes, mapped or read as open_input would take them: HPFC_OK, or
 * HPFC_E_IO / HPFC_E_NOMEM with the system's reason in *err. Release them
 * with input_unload (also after a failure). */
int input_load(const char *file, input_bytes *b, int *err);
void input_unload(input_bytes *b);

#endif
