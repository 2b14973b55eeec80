# SPDX-License-Identifier: MPL-2.0
# tests/soak/soak.mk - `make soak` (README "Soak"), included by the Makefile.
# Not part of `make check`: it runs for minutes.
#   make soak                          200000 transactions, a few minutes
#   make soak SOAK_TRANSACTIONS=1000000
SOAK_TRANSACTIONS ?= 200000
SOAK_SEED ?= 1
SOAK_SRCS := $(wildcard tests/soak/*.c)
SOAK_OBJS := $(SOAK_SRCS:%.c=$(B)/%.o) $(B)/tests/support/simproc.o

.PHONY: soak
$(B)/soak/soak: $(SOAK_OBJS) $(STATIC)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(CFLAGS) $(EXTRA) -o $@ $(SOAK_OBJS) $(STATIC) $(LIBS) -lpthread

soak: deps
	$(MAKE) all $(B)/soak/soak
	DF1_BIN=$(abspath $(B))/bin $(B)/soak/soak -n $(SOAK_TRANSACTIONS) -s $(SOAK_SEED)
$(SOAK_SRCS:%.c=$(B)/%.o): tests/soak/soak.h
