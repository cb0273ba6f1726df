/* The ATTR and EDGF sections (spec/hpfc-format.md §6.3, §6.4), shared by
 * the writer (write.c) and the reader (file.c, attrs.c). */
#ifndef HPFC_ATTRS_H
#define HPFC_ATTRS_H

#include <stdbool.h>

#include "diag.h"
#include "feature_links.h"

/* Checks an attribute table for the writer and computes the section's
 * length (HPFC_E_ARG on an inconsistent table, HPFC_E_LIMIT beyond the
 * format's sizes). */
int attr_section_length(const hpfc_attr_table *t, uint64_t *length, hpfc_diag *diag);
/* Writes the section (attr_section_length() bytes, zeroed by the caller). */
void attr_section_emit(const hpfc_attr_table *t, uint8_t *out);
/* The open-time check, O(1): reserved bytes zero, the parts add up to the
 * section's length. HPFC_E_SECTION otherwise. */
int attr_section_check(const uint8_t *section, uint64_t length);

int edgf_section_length(const hpfc_edge_feature_table *t, uint64_t *length, hpfc_diag *diag);
void edgf_section_emit(const hpfc_edge_feature_table *t, uint8_t *out);
int edgf_section_check(const uint8_t *section, uint64_t length);
/* EDGF's edge links (feature_links.h), for hpfc_edge_feature* and the
 * shapes' index: HPFC_E_ARG when !out_ok, HPFC_E_NO_SECTION without EDGF. */
int attrs_edge_links(const hpfc_file *file, bool out_ok, feature_links *links);

#endif
