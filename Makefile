# SPDX-License-Identifier: MPL-2.0
# libdf1 - GNU Makefile (no autotools). See README.
VERSION := $(shell sed -n 's/^\#define DF1_VERSION_STRING "\(.*\)"/\1/p' include/df1.h)
MAJOR := $(word 1,$(subst ., ,$(VERSION)))
MINOR := $(word 2,$(subst ., ,$(VERSION)))

PREFIX ?= /usr/local
BINDIR ?= $(PREFIX)/bin
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
MANDIR ?= $(PREFIX)/share/man
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
# systemd looks in /usr/local/lib/systemd/system too; Debian's /usr is /lib/...
SYSTEMDUNITDIR ?= $(PREFIX)/lib/systemd/system
# Lua plugins folder of Debian's wireshark (dpkg -L libwireshark16:
# /usr/lib/x86_64-linux-gnu/wireshark/plugins), so PREFIX=/usr is found at once
MULTIARCH ?= $(shell $(CC) -print-multiarch 2>/dev/null)
WIRESHARK_PLUGINDIR ?= $(PREFIX)/lib/$(if $(MULTIARCH),$(MULTIARCH)/)wireshark/plugins

CC ?= cc
# a cross build names the target's tools: CC=aarch64-linux-gnu-gcc
# AR=aarch64-linux-gnu-ar PKG_CONFIG=aarch64-linux-gnu-pkg-config (as
# scripts/cross-check.sh and dh_auto_build do); make's own AR is ar
PKG_CONFIG ?= pkg-config
CFLAGS ?= -O2 -g
WERROR ?=
# _FILE_OFFSET_BITS=64: 64-bit off_t, ino_t and directory offsets on 32-bit
# targets too (armhf: readdir fails with EOVERFLOW on a 64-bit kernel's
# directory offsets without it); no off_t is in the public headers. time_t
# stays the platform's default (df1_recv_raw takes a struct timespec, which
# a program built for the same distribution must see the same).
DF1_CFLAGS = -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE -D_FILE_OFFSET_BITS=64 -Wall -Wextra -Wshadow -Wstrict-prototypes \
	-Wmissing-prototypes -Wpointer-arith -Wformat=2 -Wno-format-nonliteral -Wundef -Wvla \
	-fvisibility=hidden -Iinclude $(WERROR)
SAN_FLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined

# B is the build directory: build/ normally, build/san/ for the sanitizer pass.
B ?= build
ifeq ($(SAN),1)
  EXTRA = $(SAN_FLAGS) -O1 -g
else
  EXTRA =
endif

# lib/ is the hub (handle.c, df1_int.h) over a folder per layer or wing
# (doc/ARCHITECTURE.md): an include names the folder it reaches into
# ("link/link.h"), so lib/ is the only include path of the library's own
# headers. tools/ sees the public headers and tools/ (common/, df1gw/, ...);
# the tests see both.
LIB_CPPFLAGS = -Ilib
TOOL_CPPFLAGS = -Itools
TEST_CPPFLAGS = -Ilib -Itools -Itests

LIBS = -lcsv -lm
CMOCKA_LIBS = $(shell $(PKG_CONFIG) --libs cmocka 2>/dev/null || echo -lcmocka)

LIB_SRCS := $(sort $(wildcard lib/*.c lib/*/*.c))
LIB_OBJS := $(LIB_SRCS:%.c=$(B)/%.o)
LIB_PIC_OBJS := $(LIB_SRCS:%.c=$(B)/pic/%.o)
TOOL_NAMES := df1read df1write df1mon df1sim df1gw
# A one-file tool is tools/NAME.c; a program of several files is the folder
# tools/NAME/ (its main is tools/NAME/NAME.c). tools/common/ is the code every
# tool shares, linked as one internal archive (libdf1-tools.a, not installed).
TOOL_SRCS_df1read := tools/df1read.c
TOOL_SRCS_df1write := tools/df1write.c
TOOL_SRCS_df1mon := $(sort $(wildcard tools/df1mon/*.c))
TOOL_SRCS_df1sim := $(sort $(wildcard tools/df1sim/*.c))
TOOL_SRCS_df1gw := $(sort $(wildcard tools/df1gw/*.c))
TOOL_LIBS_df1gw := $(shell $(PKG_CONFIG) --libs libmosquitto 2>/dev/null || echo -lmosquitto)
# OpenSSL (optional): why the broker's certificate did not verify (gw_mqtt.c)
ifeq ($(shell $(PKG_CONFIG) --exists openssl 2>/dev/null && echo 1),1)
  TOOL_LIBS_df1gw += $(shell $(PKG_CONFIG) --libs openssl)
  $(B)/tools/df1gw/gw_mqtt.o: TOOL_CPPFLAGS += -DGW_HAVE_OPENSSL
endif
# --http (tools/df1gw/gw_http.c): libmicrohttpd, and its headers' flags
TOOL_LIBS_df1gw += $(shell $(PKG_CONFIG) --libs libmicrohttpd 2>/dev/null || echo -lmicrohttpd) -lm
# df1gw's modules that need no broker library, linked into its unit tests
GW_PURE_OBJS := $(patsubst %.c,$(B)/%.o,$(filter-out tools/df1gw/df1gw.c tools/df1gw/gw_mqtt.c tools/df1gw/gw_pub.c,$(TOOL_SRCS_df1gw)))
# ... and not the health side that reads the broker's state and serves HTTP
GW_PURE_OBJS := $(filter-out $(patsubst %,$(B)/tools/df1gw/%.o,gw_health gw_http gw_metrics gw_status),$(GW_PURE_OBJS))
# Receive rows (gw_receive.c) publish through the broker
GW_PURE_OBJS := $(filter-out $(B)/tools/df1gw/gw_receive.o,$(GW_PURE_OBJS))
# store and forward's wiring (gw_sfwd.c) sees struct gw and the broker: not pure either
GW_PURE_OBJS := $(filter-out $(B)/tools/df1gw/gw_sfwd.o,$(GW_PURE_OBJS))
# Sparkplug B (df1gw --sparkplug): C made from tools/df1gw/spb.proto by protoc-c
# into the build directory, linked with libprotobuf-c; gw_spb_codec.c is the
# only file that includes it, and df1gw's unit tests link it too.
SPB_GEN_DIR := $(B)/gen/df1gw
SPB_GEN_OBJ := $(SPB_GEN_DIR)/spb.pb-c.o
PROTOBUF_C_CFLAGS := $(shell $(PKG_CONFIG) --cflags libprotobuf-c 2>/dev/null)
PROTOBUF_C_LIBS := $(shell $(PKG_CONFIG) --libs libprotobuf-c 2>/dev/null || echo -lprotobuf-c)
TOOL_LIBS_df1gw += $(SPB_GEN_OBJ) $(PROTOBUF_C_LIBS)
GW_PURE_OBJS += $(SPB_GEN_OBJ)
GW_TEST_LIBS := $(PROTOBUF_C_LIBS)
# store and forward (tools/df1gw/gw_buffer*.c): SQLite, in df1gw and its tests
SQLITE3_LIBS := $(shell $(PKG_CONFIG) --libs sqlite3 2>/dev/null || echo -lsqlite3)
TOOL_LIBS_df1gw += $(SQLITE3_LIBS)
GW_TEST_LIBS += $(SQLITE3_LIBS)
TOOL_COMMON_SRCS := $(sort $(wildcard tools/common/*.c))
TOOL_COMMON_LIB := $(B)/libdf1-tools.a
TOOLS := $(foreach t,$(TOOL_NAMES),$(B)/bin/$(t))
TOOL_HDRS := $(wildcard tools/*/*.h)
# A unit test is tests/unit/<folder>/test_*.c, <folder> the lib wing or tool
# it tests (tests/README); its binary is $(B)/tests/test_* (names are unique).
# tests/support/*.c (mocks, helpers, fixtures) are linked into every test;
# the tests in tests/unit/df1gw/ also link df1gw's broker-free objects.
TEST_SRCS := $(sort $(wildcard tests/unit/*/test_*.c))
TEST_BINS := $(patsubst %.c,$(B)/tests/%,$(notdir $(TEST_SRCS)))
TEST_HELPERS := $(wildcard tests/support/*.c)
TEST_HELPER_OBJS := $(TEST_HELPERS:%.c=$(B)/%.o)
TEST_DUPS := $(strip $(foreach n,$(sort $(notdir $(TEST_SRCS))),$(if $(word 2,$(filter %/$(n),$(TEST_SRCS))),$(filter %/$(n),$(TEST_SRCS)))))
ifneq ($(TEST_DUPS),)
  $(error unit tests with the same name (their binaries would clash): $(TEST_DUPS))
endif
ifneq ($(wildcard tests/test_*.c),)
  $(error $(wildcard tests/test_*.c): a unit test goes to tests/unit/<folder>/ (tests/README))
endif
# examples/*.c are built with the tests (tests/integration/*.sh run them)
EXAMPLE_BINS := $(patsubst examples/%.c,$(B)/examples/%,$(wildcard examples/*.c))

STATIC := $(B)/libdf1.a
# libdf1.so.MAJOR.MINOR, soname libdf1.so.MAJOR (an ABI break bumps MAJOR)
SO_FILE := libdf1.so.$(MAJOR).$(MINOR)
SHARED := $(B)/$(SO_FILE)

# The tools link libdf1 statically by default (they run from the build tree as
# they are); TOOLS_LIB=shared links them against libdf1.so.MAJOR instead, as a
# distribution package does (the tests then find it with LD_LIBRARY_PATH).
TOOLS_LIB ?= static
ifeq ($(TOOLS_LIB),shared)
  TOOL_LIB_DEP = $(SHARED)
  TOOL_LIB_LINK = -L$(B) -l:libdf1.so.$(MAJOR)
  TEST_ENV = LD_LIBRARY_PATH=$(abspath $(B))$${LD_LIBRARY_PATH:+:$$LD_LIBRARY_PATH}
else
  TOOL_LIB_DEP = $(STATIC)
  TOOL_LIB_LINK = $(STATIC)
  TEST_ENV =
endif

# keep objects of chained rules (tools, tests) for quick rebuilds
.SECONDARY:

.PHONY: all check test-run tests install uninstall install-wireshark uninstall-wireshark clean demo bench \
	lint-man lint-code check-exports deps fuzz fuzz-build cross-check
all: $(STATIC) $(SHARED) $(TOOLS) $(B)/libdf1.pc

# V=1 shows the full commands
ifeq ($(V),1)
  Q =
else
  Q = @
endif

LIB_HDRS := $(wildcard include/*.h lib/*.h lib/*/*.h)
COMPILE = $(Q)mkdir -p $(dir $@); $(if $(Q),echo "  CC      $@";) \
	$(CC) $(CPPFLAGS) $(CFLAGS) $(EXTRA) $(DF1_CFLAGS)

$(B)/lib/%.o: lib/%.c $(LIB_HDRS)
	$(COMPILE) $(LIB_CPPFLAGS) -c -o $@ $<
$(B)/tools/%.o: tools/%.c $(wildcard include/*.h) $(TOOL_HDRS)
	$(COMPILE) $(TOOL_CPPFLAGS) -c -o $@ $<
$(B)/tests/%.o: tests/%.c $(LIB_HDRS) $(TOOL_HDRS) $(wildcard tests/support/*.h)
	$(COMPILE) $(TEST_CPPFLAGS) -c -o $@ $<

$(B)/pic/lib/%.o: lib/%.c $(LIB_HDRS)
	$(COMPILE) $(LIB_CPPFLAGS) -fPIC -c -o $@ $<

$(STATIC): $(LIB_OBJS)
	@rm -f $@
	@$(if $(Q),echo "  AR      $@")
	$(Q)$(AR) rcs $@ $^

$(SHARED): $(LIB_PIC_OBJS) lib/libdf1.map
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(CFLAGS) $(EXTRA) $(LDFLAGS) -shared -Wl,-soname,libdf1.so.$(MAJOR) \
		-Wl,--version-script=lib/libdf1.map -o $@ $(LIB_PIC_OBJS) $(LIBS)
	$(Q)ln -sf $(SO_FILE) $(B)/libdf1.so.$(MAJOR)
	$(Q)ln -sf libdf1.so.$(MAJOR) $(B)/libdf1.so

$(TOOL_COMMON_LIB): $(TOOL_COMMON_SRCS:%.c=$(B)/%.o)
	@rm -f $@
	@$(if $(Q),echo "  AR      $@")
	$(Q)$(AR) rcs $@ $^

# each program: its own objects, the tools' archive, libdf1
define TOOL_RULE
$(B)/bin/$(1): $$(TOOL_SRCS_$(1):%.c=$$(B)/%.o) $$(TOOL_COMMON_LIB) $$(TOOL_LIB_DEP)
	@mkdir -p $$(dir $$@)
	@$$(if $$(Q),echo "  LD      $$@")
	$$(Q)$$(CC) $$(CFLAGS) $$(EXTRA) $$(LDFLAGS) -o $$@ $$(TOOL_SRCS_$(1):%.c=$$(B)/%.o) $$(TOOL_COMMON_LIB) \
		$$(TOOL_LIB_LINK) $$(LIBS) $$(TOOL_LIBS_$(1)) -lpthread
endef
$(foreach t,$(TOOL_NAMES),$(eval $(call TOOL_RULE,$(t))))

# Sparkplug B: the generated code (its own warnings are protoc-c's, not ours)
$(SPB_GEN_DIR)/spb.pb-c.c $(SPB_GEN_DIR)/spb.pb-c.h: tools/df1gw/spb.proto
	$(Q)mkdir -p $(SPB_GEN_DIR)
	@$(if $(Q),echo "  PROTOC  $@")
	$(Q)protoc-c --proto_path=tools/df1gw --c_out=$(SPB_GEN_DIR) spb.proto
$(SPB_GEN_OBJ): $(SPB_GEN_DIR)/spb.pb-c.c
	$(Q)mkdir -p $(dir $@); $(if $(Q),echo "  CC      $@";) \
	$(CC) $(CPPFLAGS) $(CFLAGS) $(EXTRA) $(PROTOBUF_C_CFLAGS) -I$(SPB_GEN_DIR) -c -o $@ $<
$(B)/tools/df1gw/gw_spb_codec.o: $(SPB_GEN_DIR)/spb.pb-c.h
$(B)/tools/df1gw/gw_spb_codec.o: TOOL_CPPFLAGS += -I$(SPB_GEN_DIR) $(PROTOBUF_C_CFLAGS)
$(B)/bin/df1gw: $(SPB_GEN_OBJ)

$(B)/libdf1.pc: libdf1.pc.in include/df1.h
	$(Q)sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' \
	    -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' -e 's|@VERSION@|$(VERSION)|' $< > $@

# each test binary from its object under tests/unit/<folder>/; df1gw's unit
# tests also link its broker-free objects
define TEST_RULE
$(B)/tests/$(notdir $(1:.c=)): $(B)/$(1:.c=.o) $(TEST_HELPER_OBJS) $(STATIC) \
		$(if $(filter tests/unit/df1gw/%,$(1)),$(GW_PURE_OBJS) $(TOOL_COMMON_LIB))
	@mkdir -p $$(dir $$@)
	@$$(if $$(Q),echo "  LD      $$@")
	$$(Q)$$(CC) $$(CFLAGS) $$(EXTRA) $$(LDFLAGS) -o $$@ $$< \
		$(if $(filter tests/unit/df1gw/%,$(1)),$$(GW_PURE_OBJS) $$(TOOL_COMMON_LIB)) \
		$$(TEST_HELPER_OBJS) $$(STATIC) $$(CMOCKA_LIBS) $$(LIBS) $(if $(filter tests/unit/df1gw/%,$(1)),$$(GW_TEST_LIBS)) -lpthread
endef
$(foreach t,$(TEST_SRCS),$(eval $(call TEST_RULE,$(t))))

$(B)/examples/%: examples/%.c $(wildcard include/*.h) $(STATIC)
	$(COMPILE) $(LDFLAGS) -o $@ $< $(STATIC) $(LIBS) -lpthread

tests: all $(TEST_BINS) $(EXAMPLE_BINS)

# Run every test binary and shell test; the runner's last line is "N passed, N failed".
# It is given the binaries this tree builds, so a stale one left in $(B)/tests
# (a test renamed or split) is not run.
test-run: tests
	@B=$(B) TEST_BINS="$(sort $(TEST_BINS))" $(TEST_ENV) sh tests/run-tests.sh

deps:
	@sh scripts/deps.sh

# The tree built for ARCH (arm64, armhf, s390x) with the target's compiler and
# libraries into build/cross-ARCH, its tests run under qemu-user
# (scripts/cross-check.sh; QUICK=1: the unit tests only, as CI runs them)
cross-check:
	@B=build/cross-$(ARCH) sh scripts/cross-check.sh "$(ARCH)" $(if $(filter 1,$(QUICK)),--quick)

check: deps
	$(MAKE) lint-man lint-code check-exports
	$(MAKE) B=build test-run
	$(MAKE) B=build/san SAN=1 test-run

check-exports: $(SHARED)
	@bad=$$(nm -D --defined-only $(SHARED) | awk '{print $$3}' | grep -v '^df1_' | grep -v '^LIBDF1' || true); \
	if [ -n "$$bad" ]; then echo "exported symbols without df1_ prefix: $$bad"; exit 1; fi; \
	echo "exports: only df1_* symbols"

lint-man:
	@sh tests/lint/lint-man.sh

# The layers of doc/ARCHITECTURE.md 2 kept: no two files or layers that call each other,
# no bare catalog ID in code (DF1_ID_* names), no source file over 1000 lines.
CODE_SRCS = $(wildcard include/*.h) $(wildcard lib/*.[ch] lib/*/*.[ch] tools/*.[ch] tools/*/*.[ch])
lint-code: all
	@B=$(B) sh tests/lint/lint-layers.sh
	@python3 tests/lint/lint-ids.py $(CODE_SRCS) && echo "catalog IDs: named in code"
	@sh tests/lint/lint-spdx.sh
	@long=$$(wc -l $(CODE_SRCS) | awk '$$2 != "total" && $$1 > 1000 { print $$2 " (" $$1 " lines)" }'); \
	if [ -n "$$long" ]; then echo "source files over 1000 lines: $$long"; exit 1; fi; \
	echo "source files: none over 1000 lines"

demo: deps
	$(MAKE) all
	@sh scripts/demo.sh $(B)

bench: deps
	$(MAKE) all
	@sh bench/run.sh $(B)

install: all install-wireshark
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(INCLUDEDIR) \
		$(DESTDIR)$(PKGCONFIGDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(MANDIR)/man3 $(DESTDIR)$(MANDIR)/man7
	install -m 755 $(TOOLS) $(DESTDIR)$(BINDIR)/
	install -m 644 $(STATIC) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf $(SO_FILE) $(DESTDIR)$(LIBDIR)/libdf1.so.$(MAJOR)
	ln -sf libdf1.so.$(MAJOR) $(DESTDIR)$(LIBDIR)/libdf1.so
	install -m 644 include/df1.h include/df1_catalog.h include/df1_eip.h include/df1_probe.h include/df1_server.h \
		$(DESTDIR)$(INCLUDEDIR)/
	# generated here, so that the PREFIX of this install is the one recorded
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' \
	    -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' -e 's|@VERSION@|$(VERSION)|' libdf1.pc.in \
	    > $(DESTDIR)$(PKGCONFIGDIR)/libdf1.pc
	for f in man/man1/*.1; do [ -f "$$f" ] && install -m 644 $$f $(DESTDIR)$(MANDIR)/man1/; done; true
	for f in man/man3/*.3; do [ -f "$$f" ] && install -m 644 $$f $(DESTDIR)$(MANDIR)/man3/; done; true
	for f in man/man7/*.7; do [ -f "$$f" ] && install -m 644 $$f $(DESTDIR)$(MANDIR)/man7/; done; true
	install -d $(DESTDIR)$(SYSTEMDUNITDIR)
	sed -e 's|@BINDIR@|$(BINDIR)|' contrib/systemd/df1gw@.service.in \
	    > $(DESTDIR)$(SYSTEMDUNITDIR)/df1gw@.service
	chmod 644 $(DESTDIR)$(SYSTEMDUNITDIR)/df1gw@.service

install-wireshark:
	install -d $(DESTDIR)$(WIRESHARK_PLUGINDIR)
	install -m 644 contrib/wireshark/df1.lua $(DESTDIR)$(WIRESHARK_PLUGINDIR)/

uninstall-wireshark:
	rm -f $(DESTDIR)$(WIRESHARK_PLUGINDIR)/df1.lua

uninstall: uninstall-wireshark
	rm -f $(TOOL_NAMES:%=$(DESTDIR)$(BINDIR)/%)
	rm -f $(DESTDIR)$(LIBDIR)/libdf1.a $(DESTDIR)$(LIBDIR)/libdf1.so*
	rm -f $(DESTDIR)$(INCLUDEDIR)/df1.h $(DESTDIR)$(INCLUDEDIR)/df1_catalog.h $(DESTDIR)$(INCLUDEDIR)/df1_eip.h \
		$(DESTDIR)$(INCLUDEDIR)/df1_probe.h $(DESTDIR)$(INCLUDEDIR)/df1_server.h \
		$(DESTDIR)$(PKGCONFIGDIR)/libdf1.pc
	for f in man/man1/*.1; do rm -f $(DESTDIR)$(MANDIR)/man1/$$(basename $$f); done
	for f in man/man3/*.3; do rm -f $(DESTDIR)$(MANDIR)/man3/$$(basename $$f); done
	for f in man/man7/*.7; do rm -f $(DESTDIR)$(MANDIR)/man7/$$(basename $$f); done
	rm -f $(DESTDIR)$(SYSTEMDUNITDIR)/df1gw@.service

clean:
	rm -rf build

include tests/soak/soak.mk
include tests/fuzz/fuzz.mk
