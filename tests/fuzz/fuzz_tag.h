/* SPDX-License-Identifier: MPL-2.0 */
/*
 * fuzz_tag - what the fuzz targets that turn a payload into a tag's values
 * share (fuzz_gw_set.c, fuzz_spb_cmd.c): the tag picked by one input byte,
 * its current state, and the properties every converted value keeps.
 */
#ifndef LIBDF1_FUZZ_TAG_H
#define LIBDF1_FUZZ_TAG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "df1.h"

#define FUZZ_TAG_VALUES 10      /* the most values a picked tag has (Count 10) */

/* The tag of byte o: bits 0-3 its address (fuzz_tag.c's table), bits 4-5 its
 * Count 1, 2, 4 or 10, with wider and bit 7 a wider Type where one fits
 * (DINT, or REAL for an even address index). */
void fuzz_tag_of(uint8_t o, bool wider, struct df1_tag_config *c);
/* cur: c's state, with FUZZ_TAG_VALUES zero values of its kind in curv, a
 * value or not (has_value: the members a T/C/R write leaves as they are). */
void fuzz_tag_state(const struct df1_tag_config *c, bool has_value, struct df1_tag_state *cur,
                    struct df1_value curv[FUZZ_TAG_VALUES]);
/* n converted values v for c: 1..Count of the tag's kind, finite floats,
 * strings of at most DF1_STRING_MAX bytes. */
void fuzz_tag_check_values(const struct df1_tag_config *c, const struct df1_value *v, size_t n);

#endif
