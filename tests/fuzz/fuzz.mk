# SPDX-License-Identifier: MPL-2.0
# tests/fuzz/fuzz.mk - libFuzzer targets (make fuzz; tests/fuzz/README).
# Built with clang into build/fuzz from their own objects of lib/ (and of the
# tools/ and tests/ files a target needs), so the normal build is untouched.
# `make fuzz FUZZ_SECONDS=N` runs every target N seconds and fails on any
# finding: a crash, a sanitizer report, a leak, a violated property (abort),
# a timeout or running out of memory. make check does not depend on it.

FUZZ_CC ?= clang
FUZZ_SECONDS ?= 60
# seconds one input may take before it counts as a hang
FUZZ_TIMEOUT ?= 10
# the longest input tried (bytes; the seeds longer than this are cut)
FUZZ_MAX_LEN ?= 4096
# extra libFuzzer flags for every run, e.g. FUZZ_FLAGS=-jobs=2
FUZZ_FLAGS ?=
# targets run at once (each on one core; a target's output is printed whole
# when it ends)
FUZZ_JOBS ?= 2
FUZZ_B := build/fuzz
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
# DF1_FUZZ_HOOKS: what the code records for a target to judge by (e.g.
# tools/df1gw/gw_http.h gw_http_served); absent from every other build
FUZZ_CFLAGS = -O1 -g $(FUZZ_SAN) -fsanitize=fuzzer-no-link $(DF1_CFLAGS) -DDF1_FUZZ_HOOKS -Itests/fuzz $(TEST_CPPFLAGS)

FUZZ_TARGETS := frame pccc_reply pccc_command addr value net_csv map_csv table_file mon_read link poll
FUZZ_TARGETS += eip
# df1gw's .../set payloads: its JSON reader, the values for a tag, the result
FUZZ_TARGETS += gw_set
FUZZ_EXTRA_gw_set := $(patsubst %.c,$(FUZZ_B)/%.o,tools/df1gw/gw_json.c tools/df1gw/gw_write.c \
	tools/df1gw/gw_value.c tools/common/cli_text.c tests/fuzz/fuzz_tag.c)
FUZZ_DICT_gw_set := json
# Sparkplug B commands: the protobuf payload (protobuf-c's code made from
# tools/df1gw/spb.proto by the main Makefile) and the values for a tag
FUZZ_TARGETS += spb_cmd
FUZZ_SPB_GEN_OBJ := $(FUZZ_B)/gen/df1gw/spb.pb-c.o
FUZZ_EXTRA_spb_cmd := $(patsubst %.c,$(FUZZ_B)/%.o,tools/df1gw/gw_spb_codec.c tools/df1gw/gw_spb_cmd.c \
	tools/df1gw/gw_spb_metrics.c tools/df1gw/gw_value.c tools/df1gw/gw_json.c tools/common/cli_text.c \
	tests/fuzz/fuzz_tag.c) \
	$(FUZZ_SPB_GEN_OBJ)
FUZZ_LIBS_spb_cmd := $(PROTOBUF_C_LIBS)
FUZZ_DICT_spb_cmd := spb
# rfc2217://: the Telnet framing of a device server's bytes (lib/proto/telnet.c)
FUZZ_TARGETS += telnet
FUZZ_DICT_telnet := telnet
# df1gw --http: a gateway set up whole (gw_setup()), its HTTP server fed one
# client connection per input; df1gw.c's main() renamed out of libFuzzer's way
FUZZ_TARGETS += http
FUZZ_GW_OBJS := $(patsubst %.c,$(FUZZ_B)/%.o,$(TOOL_SRCS_df1gw) $(TOOL_COMMON_SRCS))
FUZZ_EXTRA_http := $(FUZZ_GW_OBJS) $(FUZZ_SPB_GEN_OBJ)
FUZZ_LIBS_http := $(filter-out $(SPB_GEN_OBJ),$(TOOL_LIBS_df1gw))
FUZZ_DICT_http := http
$(FUZZ_B)/tools/df1gw/df1gw.o: FUZZ_CFLAGS += -Dmain=df1gw_main -Wno-missing-prototypes
FUZZ_BINS := $(FUZZ_TARGETS:%=$(FUZZ_B)/bin/fuzz_%)
FUZZ_LIB_OBJS := $(LIB_SRCS:%.c=$(FUZZ_B)/%.o)
FUZZ_COMMON_OBJS := $(FUZZ_B)/tests/fuzz/fuzz_file.o
# df1mon's --read: the pcap/raw reader, the pcap format, its stream and the decoded lines
# (and the tools' shared cli code: the decoder takes the link options from it)
FUZZ_MON_OBJS := $(patsubst %.c,$(FUZZ_B)/%.o,tools/df1mon/mon_read.c tools/df1mon/mon_pcap.c \
	tools/df1mon/mon_stream.c tools/df1mon/mon_radio.c \
	$(TOOL_COMMON_SRCS))
FUZZ_EXTRA_mon_read := $(FUZZ_MON_OBJS)
# the link and the poll engine run against the scripted port of the unit tests
FUZZ_EXTRA_link := $(FUZZ_B)/tests/support/mock_port.o $(FUZZ_B)/tests/fuzz/fuzz_peer.o
FUZZ_EXTRA_poll := $(FUZZ_B)/tests/support/mock_port.o $(FUZZ_B)/tests/fuzz/fuzz_peer.o
FUZZ_LIBS_link := $(CMOCKA_LIBS)
FUZZ_LIBS_poll := $(CMOCKA_LIBS)
# the dictionary of each target (tests/fuzz/*.dict, concatenated)
FUZZ_DICT_frame := df1
FUZZ_DICT_pccc_reply := df1 pccc
FUZZ_DICT_pccc_command := df1 pccc
FUZZ_DICT_addr := addr
FUZZ_DICT_value := addr value
FUZZ_DICT_net_csv := csv
FUZZ_DICT_map_csv := csv addr
FUZZ_DICT_table_file := csv addr value
FUZZ_DICT_mon_read := df1 pcap
FUZZ_DICT_link := df1 pccc
FUZZ_DICT_poll := df1 pccc
FUZZ_DICT_eip := eip

FUZZ_COMPILE = $(Q)mkdir -p $(dir $@); $(if $(Q),echo "  FUZZCC  $@";) $(FUZZ_CC) $(FUZZ_CFLAGS)

$(FUZZ_B)/lib/%.o: lib/%.c $(LIB_HDRS)
	$(FUZZ_COMPILE) -c -o $@ $<
$(FUZZ_B)/tools/%.o: tools/%.c $(wildcard include/*.h) $(TOOL_HDRS)
	$(FUZZ_COMPILE) -c -o $@ $<
$(FUZZ_B)/tests/%.o: tests/%.c $(LIB_HDRS) $(wildcard tests/support/*.h) $(wildcard tests/fuzz/*.h)
	$(FUZZ_COMPILE) -c -o $@ $<

$(FUZZ_SPB_GEN_OBJ): $(SPB_GEN_DIR)/spb.pb-c.c
	$(FUZZ_COMPILE) $(PROTOBUF_C_CFLAGS) -I$(SPB_GEN_DIR) -c -o $@ $<
$(FUZZ_B)/tools/df1gw/gw_spb_codec.o: $(SPB_GEN_DIR)/spb.pb-c.h
$(FUZZ_B)/tools/df1gw/gw_spb_codec.o: FUZZ_CFLAGS += -I$(SPB_GEN_DIR) $(PROTOBUF_C_CFLAGS)

$(FUZZ_B)/libdf1.a: $(FUZZ_LIB_OBJS)
	@rm -f $@
	$(Q)ar rcs $@ $^

.SECONDEXPANSION:
$(FUZZ_B)/bin/fuzz_%: $(FUZZ_B)/tests/fuzz/fuzz_%.o $(FUZZ_COMMON_OBJS) $$(FUZZ_EXTRA_$$*) $(FUZZ_B)/libdf1.a
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  FUZZLD  $@")
	$(Q)$(FUZZ_CC) -g $(FUZZ_SAN) -fsanitize=fuzzer -o $@ $< $(FUZZ_COMMON_OBJS) \
		$(FUZZ_EXTRA_$*) $(FUZZ_B)/libdf1.a $(FUZZ_LIBS_$*) $(LIBS) -lpthread

$(FUZZ_B)/dict/%.dict: $$(foreach d,$$(FUZZ_DICT_$$*),tests/fuzz/$$(d).dict)
	@mkdir -p $(dir $@)
	$(Q)cat $^ > $@

# The seed corpora, generated from the spec vectors, the captures and tests/data,
# and the inputs of past findings (tests/fuzz/found/TARGET-*.hex). Made anew
# each time, so a seed removed from the sources leaves the corpus too.
$(FUZZ_B)/seeds/.stamp: tests/fuzz/seeds.py tests/data/vectors.txt $(wildcard tests/data/*) $(wildcard tests/fuzz/found/*)
	$(Q)rm -rf $(FUZZ_B)/seeds/*/
	$(Q)python3 tests/fuzz/seeds.py $(FUZZ_B)/seeds
	@touch $@

fuzz-build: $(FUZZ_BINS) $(FUZZ_TARGETS:%=$(FUZZ_B)/dict/%.dict) $(FUZZ_B)/seeds/.stamp

# Each target (tests/fuzz/run-target.sh): every seed replayed once, then
# FUZZ_SECONDS of fuzzing on its working corpus and its seeds; what it finds
# goes to build/fuzz/findings/TARGET-*, its output to build/fuzz/logs, and
# a finding's input is printed in hex with the command that reproduces it.
fuzz:
	@command -v $(FUZZ_CC) >/dev/null 2>&1 || { \
		echo "make fuzz: $(FUZZ_CC) not found; install clang (apt-get install -y clang) or set FUZZ_CC"; \
		exit 1; }
	$(MAKE) fuzz-build
	@mkdir -p $(FUZZ_B); rm -f $(FUZZ_B)/failed; \
	printf '%s\n' $(FUZZ_TARGETS) | FUZZ_B=$(FUZZ_B) FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_TIMEOUT=$(FUZZ_TIMEOUT) \
		FUZZ_MAX_LEN=$(FUZZ_MAX_LEN) FUZZ_FLAGS="$(FUZZ_FLAGS)" xargs -r -P $(FUZZ_JOBS) -I{} sh -c \
		'o=$$(sh tests/fuzz/run-target.sh {} 2>&1) || echo {} >> $(FUZZ_B)/failed; printf "%s\n" "$$o"'; \
	if [ -s $(FUZZ_B)/failed ]; then echo "make fuzz: findings in:" $$(cat $(FUZZ_B)/failed); exit 1; fi; \
	echo "make fuzz: $(words $(FUZZ_TARGETS)) targets, their seeds replayed and $(FUZZ_SECONDS) s each, no finding"
