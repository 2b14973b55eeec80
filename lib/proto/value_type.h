/* SPDX-License-Identifier: MPL-2.0 */
/*
 * value_type - the mapping file's Type column (libdf1(7) "Mapping file",
 * df1_tag_value_kind(3)): the names, which addresses each fits, and the
 * conversions between the values an address reads as and the declared ones.
 * Pure: no I/O, no allocation.
 *
 * A Type fits an address when it holds every value the address can have:
 * the address's own kind (INT for a word, DINT or LONG for L, REAL or FLOAT
 * for F, BOOL for a bit, STRING for ST, TIMER, COUNTER or CONTROL for a
 * whole element of that file), or a wider number for a 16-bit word (DINT,
 * REAL). A bit is BOOL only; a whole T/C/R element is never a number (its
 * words are: T4:0.ACC). Empty: the address's own.
 */
#ifndef LIBDF1_VALUE_TYPE_H
#define LIBDF1_VALUE_TYPE_H

#include "df1.h"

/* The names, for messages. */
#define VALUE_TYPE_NAMES "INT, DINT (LONG), REAL (FLOAT), BOOL, STRING, TIMER, COUNTER or CONTROL"

/* Type text (any case, blanks around) for address a: 0 and *kind, or
 * DF1_E_INVAL (not a Type) or DF1_E_TYPE (does not fit a; *why says what
 * does). type NULL or empty: the address's own kind. */
int value_type_check(const char *type, const struct df1_addr *a, enum df1_value_kind *kind, const char **why);
/* A value read from the address (its own kind) as the declared kind: a
 * widening value_type_check() allowed, exact. In place. */
void value_type_widen(struct df1_value *v, enum df1_value_kind kind);
/* A value of the declared kind as the address's kind ak, to be written: 0, or
 * DF1_E_RANGE (out of the address's range, or not a whole number for a word),
 * DF1_E_TYPE (a kind that does not convert). In place. */
int value_type_narrow(struct df1_value *v, enum df1_value_kind ak);

#endif
