/* SPDX-License-Identifier: MPL-2.0 */
/*
 * decode_int - what decode.c takes from decode_typedata.c. Not for the tools.
 */
#ifndef DF1_TOOLS_DECODE_INT_H
#define DF1_TOOLS_DECODE_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "df1.h"

/* Skip the type/data parameter in front of typed data (an array's descriptor
 * too); returns the offset of the element data and sets *ft, or -1. */
int decode_typedata_skip(const uint8_t *p, size_t n, enum df1_file_type *ft);
/* 0F/67 (app: its bytes from DST; data: where df1_msg_decode puts its data):
 * true when the bytes before data are the system address and a type/data
 * parameter, *ft then the element type from it. */
bool decode_typedata_before(const uint8_t *app, const uint8_t *data, enum df1_file_type *ft);
/* The file type element values of an address decode as. */
enum df1_file_type decode_value_file_type(const struct df1_addr *a);

#endif
