-- SPDX-License-Identifier: MPL-2.0
-- df1.lua - Allen-Bradley DF1 / PCCC dissector for Wireshark and tshark 4.x (Lua 5.2).
--
-- Dissects DF1 in RTAC-serial records (pcap link type 250, as serial taps and
-- `df1mon --sniff -w` write them) at once, and raw DF1 over TCP on a port
-- chosen in the preferences (off by default). The bytes of each direction are
-- one stream: symbols and frames split over several records are reassembled and
-- shown on the record that completes them. Decoding follows libdf1's
-- doc/PROTOCOL.md and prints what `df1mon --read` prints: the decoder below
-- mirrors lib/proto/frame.c (DLE stuffing, BCC/CRC auto-detection, duplex
-- auto-detection), the message decoding mirrors tools/common/decode.c. The
-- "Link mode" preference reads a DF1 Radio Modem channel as df1mon --duplex
-- radio does (tools/df1mon/mon_radio.c): no link symbols expected, a packet
-- heard again unchanged marked as a store-and-forward relay's copy.
--
-- Load it with `tshark -X lua_script:df1.lua`, or copy it into a Lua plugin
-- folder (~/.local/lib/wireshark/plugins/). Frames cut by the end of a capture,
-- and replies' links to later frames, need all records read first: use
-- `tshark -2` (Wireshark always has them).

local df1 = Proto("df1", "Allen-Bradley DF1")

-- ---------------------------------------------------------------- constants

local DLE, SOH, STX, ETX, EOT, ENQ, ACK, NAK, NAK_OLD = 0x10, 0x01, 0x02, 0x03, 0x04, 0x05,
	0x06, 0x15, 0x0F
local MAX_DATA, MIN_DATA = 264, 6        -- lib/proto/frame.h
local MAX_VALUES = 160                   -- tools/common/decode.c
local DECODE_CMDS = 64                   -- tools/common/decode.h
local RTAC_HDR = 12
local WTAP_RTAC_SERIAL = wtap_encaps and wtap_encaps.RTAC_SERIAL or 153

-- catalog IDs of the decoder's errors (doc/REQUIREMENTS.md 004)
local ID_ERR_BAD_BCC, ID_TOO_LONG, ID_TOO_SHORT, ID_INVALID_SYMBOL, ID_NO_ETX =
	2507, 2512, 2513, 2514, 2518
local ID_NAMES = {
	[2507] = "ERR_BAD_BCC", [2512] = "NTC_RCVD_MSG_TOO_LONG", [2513] = "NTC_RCVD_MSG_TOO_SHORT",
	[2514] = "NTC_INVALID_SYMBOL", [2518] = "NTC_NO_ETX_RCVD",
}

local band, bor, bxor, rshift, lshift = bit32.band, bit32.bor, bit32.bxor, bit32.rshift, bit32.lshift

-- CRC-16/ARC, reflected 8005h (A001h), init 0 (doc/PROTOCOL.md 1.5)
local CRC_TABLE = {}
for i = 0, 255 do
	local c = i
	for _ = 1, 8 do
		if band(c, 1) ~= 0 then c = bxor(rshift(c, 1), 0xA001) else c = rshift(c, 1) end
	end
	CRC_TABLE[i] = c
end
local function crc_step(crc, b)
	return bxor(rshift(crc, 8), CRC_TABLE[band(bxor(crc, b), 0xFF)])
end

-- ---------------------------------------------------------------- PLC tables

-- STS (M p.8-2, 8-3; lib/proto/errors.c)
local STS_LOCAL = {
	[0x00] = "success, no error",
	[0x01] = "DST node is out of buffer space",
	[0x02] = "cannot guarantee delivery: link layer (the remote node did not ACK the command)",
	[0x03] = "duplicate token holder detected",
	[0x04] = "local port is disconnected",
	[0x05] = "application layer timed out waiting for a response",
	[0x06] = "duplicate node detected",
	[0x07] = "station is offline",
	[0x08] = "hardware fault",
}
local STS_REMOTE = {
	[0x10] = "illegal command or format",
	[0x20] = "host has a problem and will not communicate",
	[0x30] = "remote node host is missing, disconnected, or shut down",
	[0x40] = "host could not complete function due to hardware fault",
	[0x50] = "addressing problem or memory protect rungs",
	[0x60] = "function not allowed due to command protection selection",
	[0x70] = "processor is in Program mode",
	[0x80] = "compatibility mode file missing or communication zone problem",
	[0x90] = "remote node cannot buffer command",
	[0xA0] = "wait ACK (1775-KA buffer full)",
	[0xB0] = "remote node problem due to download",
	[0xC0] = "wait ACK (1775-KA buffer full)",
	[0xF0] = "error code is in the EXT STS byte",
}
local EXT_STS_0F = {
	[0x00] = "not used",
	[0x01] = "a field has an illegal value",
	[0x02] = "less levels specified in address than minimum for any address",
	[0x03] = "more levels specified in address than system supports",
	[0x04] = "symbol not found",
	[0x05] = "symbol is of improper format",
	[0x06] = "address doesn't point to something usable",
	[0x07] = "file is wrong size",
	[0x08] = "cannot complete request, situation has changed since the start of the command",
	[0x09] = "data or file is too large",
	[0x0A] = "transaction size plus word address is too large",
	[0x0B] = "access denied, improper privilege",
	[0x0C] = "condition cannot be generated - resource is not available",
	[0x0D] = "condition already exists - resource is already available",
	[0x0E] = "command cannot be executed",
	[0x0F] = "histogram overflow",
	[0x10] = "no access",
	[0x11] = "illegal data type",
	[0x12] = "invalid parameter or invalid data",
	[0x13] = "address reference exists to deleted area",
	[0x14] = "command execution failure for unknown reason; possible PLC-3 histogram overflow",
	[0x15] = "data conversion error",
	[0x16] = "scanner not able to communicate with 1771 rack adapter",
	[0x17] = "type mismatch",
	[0x18] = "1771 module response was not valid",
	[0x19] = "duplicated label",
	[0x1A] = "file is open; another node owns it",
	[0x1B] = "another node is the program owner",
	[0x1C] = "reserved",
	[0x1D] = "reserved",
	[0x1E] = "data table element protection violation",
	[0x1F] = "temporary internal problem",
	[0x22] = "remote rack fault (pass-through DH+ to remote I/O)",
	[0x23] = "timeout (pass-through)",
	[0x24] = "unknown error (pass-through)",
}
local EXT_STS_DH485 = {
	[0x07] = "insufficient memory module size (0000h returned)",
	[0x0B] = "access denied, privilege violation",
	[0x0C] = "resource not available or cannot do",
	[0x0E] = "CMD cannot be executed",
	[0x12] = "invalid parameter",
	[0x14] = "failure during processing",
	[0x19] = "duplicate label",
	[0x1A] = "file open by another node",
	[0x1B] = "program owned by another node",
}

local function sts_text(sts)
	if sts == 0 then return STS_LOCAL[0] end
	local t = STS_LOCAL[band(sts, 0x0F)]
	if t and band(sts, 0x0F) ~= 0 then return t end
	return STS_REMOTE[band(sts, 0xF0)] or "unknown status"
end

local function is_dh485(cmd)
	local c = band(cmd, 0xBF)
	return c == 0x0B or c == 0x1A or c == 0x1B
end

local function ext_sts_text(cmd, ext)
	local t = is_dh485(cmd) and EXT_STS_DH485[ext] or (not is_dh485(cmd) and EXT_STS_0F[ext])
	return t or "unknown status"
end

-- command names (lib/proto/pccc.c pccc_command_name, without the code)
local CMD_NAMES = {
	[0x00] = "protected write", [0x01] = "unprotected read", [0x02] = "protected bit write",
	[0x05] = "unprotected bit write", [0x06] = "diagnostic", [0x08] = "unprotected write",
	[0x0F] = "command",
}
local FNC06 = {
	[0x00] = "echo", [0x01] = "diagnostic read", [0x02] = "set variables",
	[0x03] = "diagnostic status", [0x04] = "set timeout", [0x05] = "set NAKs",
	[0x06] = "set ENQs", [0x07] = "diagnostic counter reset",
}
local FNC0F = {
	[0x00] = "word range write", [0x01] = "word range read", [0x02] = "bit write",
	[0x26] = "read-modify-write", [0x3A] = "set CPU mode", [0x67] = "typed write",
	[0x68] = "typed read", [0x80] = "change mode",
	[0xA1] = "SLC typed read, 2 fields", [0xA2] = "SLC typed read, 3 fields",
	[0xA9] = "SLC typed write, 2 fields", [0xAA] = "SLC typed write, 3 fields",
	[0xAB] = "SLC masked write",
}

local function command_name(cmd, has_fnc, fnc)
	if band(cmd, 0x40) ~= 0 then return "reply" end
	if cmd == 0x06 then
		if not has_fnc then return "diagnostic" end
		return FNC06[fnc] or "diagnostic, unknown function"
	end
	if cmd == 0x0F then
		if not has_fnc then return "command" end
		return FNC0F[fnc] or "unknown function"
	end
	return CMD_NAMES[cmd] or "unknown command"
end

-- file types (lib/proto/addr.c ft_table): name, fixed file (-1 any of 3..999),
-- default file, element bytes, max bit, max sub-element
local FT = {
	O = { fixed = 0, default = 0, size = 2, max_bit = 15, max_sub = 255 },
	I = { fixed = 1, default = 1, size = 2, max_bit = 15, max_sub = 255 },
	S = { fixed = 2, default = 2, size = 2, max_bit = 15, max_sub = -1 },
	B = { fixed = -1, default = 3, size = 2, max_bit = 15, max_sub = -1 },
	T = { fixed = -1, default = 4, size = 6, max_bit = 15, max_sub = 2 },
	C = { fixed = -1, default = 5, size = 6, max_bit = 15, max_sub = 2 },
	R = { fixed = -1, default = 6, size = 6, max_bit = 15, max_sub = 2 },
	N = { fixed = -1, default = 7, size = 2, max_bit = 15, max_sub = -1 },
	F = { fixed = -1, default = 8, size = 4, max_bit = -1, max_sub = -1 },
	ST = { fixed = -1, default = -1, size = 84, max_bit = -1, max_sub = -1 },
	A = { fixed = -1, default = -1, size = 2, max_bit = 15, max_sub = -1 },
	L = { fixed = -1, default = -1, size = 4, max_bit = 31, max_sub = -1 },
}
local SLC_CODES = {
	[0x82] = "O", [0x8B] = "O", [0x83] = "I", [0x8C] = "I", [0x84] = "S", [0x85] = "B",
	[0x86] = "T", [0x87] = "C", [0x88] = "R", [0x89] = "N", [0x8A] = "F", [0x8D] = "ST",
	[0x8E] = "A", [0x91] = "L",
}
local WORD_NAMES = { T = { "PRE", "ACC" }, C = { "PRE", "ACC" }, R = { "LEN", "POS" } }
local BIT_NAMES = {
	T = { { "EN", 15 }, { "TT", 14 }, { "DN", 13 } },
	C = { { "CU", 15 }, { "CD", 14 }, { "DN", 13 }, { "OV", 12 }, { "UN", 11 }, { "UA", 10 } },
	R = { { "EN", 15 }, { "EU", 14 }, { "DN", 13 }, { "EM", 12 }, { "ER", 11 }, { "UL", 10 },
		{ "IN", 9 }, { "FD", 8 } },
}
local function is_tcr(t) return t == "T" or t == "C" or t == "R" end
-- A PLC-3's sections by number, its T/C words and bit names (doc/PROTOCOL.md 4.2a)
local P3_SECTIONS = { [1] = "O", [2] = "I", [3] = "T", [4] = "C", [5] = "N", [6] = "F", [7] = "D",
	[8] = "B", [9] = "A", [10] = "H", [13] = "S" }
local P3_WORDS = { [0] = "CTL", "PRE", "ACC" }
local P3_BITS = {
	T = { [15] = "EN", [14] = "TT", [13] = "DN" },
	C = { [15] = "CU", [14] = "CD", [13] = "DN", [12] = "OV", [11] = "UF" },
}
local function bit_name(t, bit)
	for _, nb in ipairs(BIT_NAMES[t] or {}) do if nb[2] == bit then return nb[1] end end
end

-- ---------------------------------------------------------------- addresses

-- addr: { type = "N" | nil, file, element, sub (nil: none), bit (nil), ascii (nil) }

-- The range and shape rules df1_addr_format checks (lib/proto/addr.c).
-- A PLC-3's text (lib/proto/addr_plc3.c): octal bits and I/O words, T4.ACC, T4/DN; nil
-- for fields it has no text for.
local function format_plc3(a)
	if a.type == "T" or a.type == "C" then
		local s = a.type .. a.element
		if a.bit and a.bit > 15 then return nil end
		if a.sub and (a.sub ~= 0 or not a.bit) then s = s .. "." .. P3_WORDS[a.sub] end
		if a.bit then
			local name = (a.sub or 0) == 0 and P3_BITS[a.type][a.bit]
			s = s .. "/" .. (name or string.format("%o", a.bit))
		end
		return s
	end
	if a.sub or ((a.type == "F" or a.type == "H") and a.bit) or (a.bit and a.bit > 15) then return nil end
	local io = a.type == "O" or a.type == "I"
	local s = a.type .. a.file .. ":" .. (io and string.format("%o", a.element) or tostring(a.element))
	if a.bit then s = s .. "/" .. string.format("%o", a.bit) end
	return s
end

local function addr_fields_ok(a)
	if a.plc3 then return format_plc3(a) ~= nil end
	local fi = a.type and FT[a.type]
	if not fi then return false end
	if a.sub and (a.sub < 0 or fi.max_sub < 0) then return false end
	if a.bit and (a.bit < 0 or fi.max_bit < 0) then return false end
	if is_tcr(a.type) and a.bit and not a.sub then return false end
	if a.file < 0 or a.file > 999 then return false end
	if fi.fixed >= 0 then
		if a.file ~= fi.fixed then return false end
	elseif a.file < 3 then
		return false
	end
	if a.element < 0 or a.element > 999 then return false end
	if a.sub and a.sub > fi.max_sub then return false end
	if a.bit and a.bit > fi.max_bit then return false end
	return true
end

-- User notation: N7:5, T4:0.ACC, T4:0/DN, B3:1/5, $N7:0; "file 7:300" for a PLC-5
-- binary address (it carries no file type) or one out of the named ranges.
local function format_addr(a)
	if a.ascii then return "$" .. a.ascii end
	if a.plc3 and format_plc3(a) then return format_plc3(a) end
	if a.type and addr_fields_ok(a) then
		local s = a.type .. a.file .. ":" .. a.element
		if is_tcr(a.type) and a.sub == 0 and a.bit then
			return s .. "/" .. (bit_name(a.type, a.bit) or tostring(a.bit))
		end
		if a.sub then
			local w = WORD_NAMES[a.type]
			s = s .. "." .. ((w and a.sub >= 1 and a.sub <= 2) and w[a.sub] or tostring(a.sub))
		end
		if a.bit then s = s .. "/" .. a.bit end
		return s
	end
	local s = "file " .. a.file .. ":" .. a.element
	if a.sub then s = s .. "." .. a.sub end
	if a.bit then s = s .. "/" .. a.bit end
	return s
end

-- The parts of df1_addr_parse a logical ASCII address needs: its type, and whether
-- it names a word or a bit (which decide how values decode). nil if not parsable.
local function parse_ascii_addr(text)
	local ty, rest = text:match("^(%a+)(.*)$")
	if not ty then return nil end
	ty = ty:upper()
	local fi = FT[ty]
	if not fi then return nil end
	local file, r2 = rest:match("^(%d*)(.*)$")
	if file == "" then
		if fi.default < 0 then return nil end
		file = fi.default
	else
		file = tonumber(file)
	end
	local a = { type = ty, file = file }
	local elem, tail = r2:match("^:(%d+)(.*)$")
	if elem then
		a.element = tonumber(elem)
		local sub, t2 = tail:match("^%.(%w+)(.*)$")
		if sub then
			local w = WORD_NAMES[ty]
			if sub:match("^%d+$") then a.sub = tonumber(sub)
			elseif w and (sub:upper() == w[1] or sub:upper() == w[2]) then
				a.sub = sub:upper() == w[1] and 1 or 2
			else
				for _, nb in ipairs(BIT_NAMES[ty] or {}) do
					if nb[1] == sub:upper() then a.sub = 0; a.bit = nb[2] end
				end
				if not a.sub then return nil end
			end
			tail = t2
		end
		local bit, t3 = tail:match("^/(%w+)(.*)$")
		if bit then
			if bit:match("^%d+$") then a.bit = tonumber(bit)
			else
				for _, nb in ipairs(BIT_NAMES[ty] or {}) do
					if nb[1] == bit:upper() then a.bit = nb[2] end
				end
				if not a.bit then return nil end
			end
			if is_tcr(ty) and not a.sub then a.sub = 0 end
			tail = t3
		end
		if tail ~= "" then return nil end
	elseif ty == "B" and r2:match("^/%d+$") then
		local n = tonumber(r2:sub(2))
		a.element, a.bit = math.floor(n / 16), n % 16
	else
		return nil
	end
	if not addr_fields_ok(a) then return nil end
	return a
end

-- The file type a command's values decode as (tools/common/decode_typedata.c).
local function value_file_type(a)
	if not a or not a.type then return "N" end
	if a.plc3 and (a.type == "H" or a.type == "D") then return a.type == "H" and "L" or "N" end
	if is_tcr(a.type) and (a.sub or a.bit) then return "N" end
	return a.type
end

-- ---------------------------------------------------------------- byte helpers

local function u8(s, i) return s:byte(i + 1) end   -- 0-based offsets into a Lua string
local function le16(s, i) return s:byte(i + 1) + 256 * s:byte(i + 2) end
local function le32(s, i) return le16(s, i) + 65536 * le16(s, i + 2) end
local function hex(s)
	local t = {}
	for i = 1, #s do t[i] = string.format("%02X", s:byte(i)) end
	return table.concat(t, " ")
end

-- SLC / PLC-5 address field: one byte, or FF + LE16 (M p.104). value, length.
local function get_field(s, i)
	if i >= #s then return nil end
	local b = u8(s, i)
	if b ~= 0xFF then return b, 1 end
	if i + 3 > #s then return nil end
	return le16(s, i + 1), 3
end

-- PLC-5 system address at offset i (doc/PROTOCOL.md 4.1): addr, length | nil, error.
local function plc5_addr(s, i)
	if i >= #s then return nil, "too short" end
	if u8(s, i) == 0 then
		if i + 1 >= #s then return nil, "too short" end
		if u8(s, i + 1) ~= 0x24 then return nil, "address syntax" end
		local j = i + 2
		while j < #s and u8(s, j) ~= 0 do j = j + 1 end
		if j >= #s then return nil, "too short" end
		local text = s:sub(i + 3, j)
		if #text > 51 then return nil, "address out of range" end
		local a = parse_ascii_addr(text) or { file = -1, element = -1 }
		a.ascii = text
		return a, j + 1 - i
	end
	local mask, k = get_field(s, i)
	if not mask then return nil, "too short" end
	local pos = i + k
	if rshift(mask, 4) ~= 0 then return nil, "address out of range" end
	local lv = { [0] = 0, 1, 0, 0 }
	for lvl = 0, 3 do
		if band(mask, lshift(1, lvl)) ~= 0 then
			local v, n = get_field(s, pos)
			if not v then return nil, "too short" end
			lv[lvl] = v
			pos = pos + n
		end
	end
	if lv[0] ~= 0 then return nil, "address out of range" end
	return { file = lv[1], element = lv[2], sub = band(mask, 8) ~= 0 and lv[3] or nil }, pos - i
end

-- Does the address at offset i look like a PLC-3's? Its mask has the word level (bit 5),
-- which no PLC-5 address has (doc/PROTOCOL.md 4.2a).
local function is_plc3_addr(s, i)
	if i >= #s then return false end
	local mask = u8(s, i)
	return band(mask, 0x20) ~= 0 and band(mask, 0xC0) == 0
end

-- PLC-3 logical binary address at offset i: levels 1 area (3, the data table), 2 context,
-- 3 section, 4 file, 5 structure, 6 word (doc/PROTOCOL.md 4.2a): addr, length | nil, error.
local function plc3_addr(s, i)
	local mask = u8(s, i)
	local lv = { [0] = 3, 0, 0, 0, 0, 0 }
	local pos = i + 1
	for lvl = 0, 5 do
		if band(mask, lshift(1, lvl)) ~= 0 then
			local v, n = get_field(s, pos)
			if not v then return nil, "too short" end
			lv[lvl] = v
			pos = pos + n
		end
	end
	local t = P3_SECTIONS[lv[2]]
	if lv[0] ~= 3 or not t or lv[3] > 999 then return nil, "address out of range" end
	local a = { plc3 = true, type = t, file = lv[3] }
	if t == "T" or t == "C" then
		if lv[3] ~= 0 or lv[4] > 9999 or lv[5] > 2 then return nil, "address out of range" end
		-- word 0: the structure from its start, shown without a member (as df1mon)
		a.element, a.sub = lv[4], lv[5] ~= 0 and lv[5] or nil
	elseif t == "F" or t == "H" then
		if lv[4] > 9999 or lv[5] > 1 then return nil, "address out of range" end
		a.element, a.sub = lv[4], lv[5] == 1 and 1 or nil
	else
		local max = (t == "O" or t == "I") and 4095 or 9999
		if lv[4] ~= 0 or lv[5] > max then return nil, "address out of range" end
		a.element = lv[5]
	end
	return a, pos - i
end

-- Type/data parameter (doc/PROTOCOL.md 4.3): type id, size, length | nil.
local function typedata(s, i)
	if i >= #s then return nil end
	local flag = u8(s, i)
	local pos = i + 1
	local id, size = rshift(flag, 4), band(flag, 0x0F)
	local function ext(k)
		if k == 0 or k > 4 or pos + k > #s then return nil end
		local v = 0
		for j = 0, k - 1 do v = v + u8(s, pos + j) * 256 ^ j end
		pos = pos + k
		return v
	end
	if band(id, 8) ~= 0 then id = ext(band(id, 7)); if not id then return nil end end
	if band(size, 8) ~= 0 then size = ext(band(size, 7)); if not size then return nil end end
	return id, size, pos - i
end

local TD_TYPES = { [3] = "ST", [8] = "F" }
local function typedata_file_type(id, size)
	if id == 4 then return size == 4 and "L" or "N" end
	if id == 5 then return size == 6 and "T" or "N" end
	if id == 6 then return size == 6 and "C" or "N" end
	if id == 7 then return size == 6 and "R" or "N" end
	return TD_TYPES[id] or "N"
end

-- The type/data parameter before typed data (an array's descriptor too):
-- offset of the element data from i, file type | nil.
local function typedata_skip(s, i)
	local id, size, k = typedata(s, i)
	if not id then return nil end
	if id == 9 then
		local eid, esize, k2 = typedata(s, i + k)
		if not eid then return nil end
		return k + k2, typedata_file_type(eid, esize)
	end
	return k, typedata_file_type(id, size)
end

-- ---------------------------------------------------------------- values

local function to_f32(x) return Struct.unpack("<f", Struct.pack("<f", x)) end

-- The shortest text that reads back to the same float, laid out like %g
-- (lib/proto/valuefmt.c).
local function format_float(f)
	if f ~= f then return "nan" end
	if f == math.huge then return "inf" end
	if f == -math.huge then return "-inf" end
	local sci
	for p = 1, 9 do
		sci = string.format("%." .. (p - 1) .. "e", f)
		if to_f32(tonumber(sci)) == f then break end
	end
	local neg = sci:sub(1, 1) == "-"
	local mant, e = sci:match("^-?([%d%.]+)e([-+]%d+)$")
	local digits = mant:gsub("%.", ""):gsub("0+$", "")
	if digits == "" then digits = "0" end
	local exp10 = tonumber(e)
	local out
	if exp10 < -4 or exp10 >= 9 then
		out = digits:sub(1, 1) .. (#digits > 1 and ("." .. digits:sub(2)) or "") ..
			string.format("e%s%02d", exp10 < 0 and "-" or "+", math.abs(exp10))
	elseif exp10 < 0 then
		out = "0." .. string.rep("0", -exp10 - 1) .. digits
	else
		local int = digits:sub(1, exp10 + 1)
		int = int .. string.rep("0", exp10 + 1 - #int)
		out = int .. (#digits > exp10 + 1 and ("." .. digits:sub(exp10 + 2)) or "")
	end
	return (neg and "-" or "") .. out
end

local function signed16(v) return v >= 0x8000 and v - 0x10000 or v end
local function signed32(v) return v >= 0x80000000 and v - 0x100000000 or v end

local function tcr_text(t, ctl, pre, acc)
	local bits = BIT_NAMES[t]
	if not bits then return string.format("CTL=0x%04X PRE=%d ACC=%d", ctl, pre, acc) end
	local parts = {}
	for _, nb in ipairs(bits) do parts[#parts + 1] = nb[1] .. "=" .. band(rshift(ctl, nb[2]), 1) end
	local w = WORD_NAMES[t]
	parts[#parts + 1] = w[1] .. "=" .. pre
	parts[#parts + 1] = w[2] .. "=" .. acc
	return table.concat(parts, " ")
end

-- One element of file type ft at offset i: value table, size | nil (too short),
-- false (not a value of that type).
local function decode_element(ft, s, i)
	local size = FT[ft].size
	if #s - i < size then return nil end
	local v = { off = i, len = size, ft = ft }
	if ft == "L" then
		v.kind, v.int = "int32", signed32(le32(s, i)); v.text = tostring(v.int)
	elseif ft == "F" then
		v.kind, v.float = "float", Struct.unpack("<f", s:sub(i + 1, i + 4)); v.text = format_float(v.float)
	elseif ft == "ST" then
		local len = le16(s, i)
		if len > 82 then return false end
		local c = {}
		for k = 0, len - 1 do c[#c + 1] = string.char(u8(s, i + 2 + bxor(k, 1))) end
		v.kind, v.string = "string", (table.concat(c):match("^[^%z]*"))
		v.text = v.string
	elseif is_tcr(ft) then
		v.kind, v.ctl, v.pre, v.acc = "tcr", le16(s, i), signed16(le16(s, i + 2)), signed16(le16(s, i + 4))
		v.text = tcr_text(ft, v.ctl, v.pre, v.acc)
	else
		v.kind, v.int = "int16", signed16(le16(s, i)); v.text = tostring(v.int)
	end
	return v, size
end

-- df1_values_decode: whole elements; a partial trailing one is not a value.
local function values_decode(ft, s, i, n)
	local out, pos = {}, i
	local sub = s:sub(1, i + n)
	while #out < MAX_VALUES and pos < i + n do
		local v, k = decode_element(ft, sub, pos)
		if v == nil then break end
		if v == false then return nil end
		out[#out + 1] = v
		pos = pos + k
	end
	return out
end

-- ---------------------------------------------------------------- message view

-- What tools/common/decode.c shows of a frame's app bytes `s`: a view table.
-- ctx: the transaction memory (commands by TNS) of this capture or TCP stream.
local function msg_decode(s)
	local m = { size = -1 }
	if #s < 6 then return m, "message too short" end
	m.dst, m.src, m.cmd, m.sts, m.tns = u8(s, 0), u8(s, 1), u8(s, 2), u8(s, 3), le16(s, 4)
	m.is_reply = band(m.cmd, 0x40) ~= 0
	local pos = 6
	if not m.is_reply then
		if m.cmd == 0x06 or m.cmd == 0x0F then
			if #s < 7 then m.name = command_name(m.cmd, false); return m, "message too short" end
			m.has_fnc, m.fnc = true, u8(s, 6)
			pos = 7
		end
	elseif m.sts == 0xF0 and band(m.cmd, 0xBF) > 0x08 then
		if #s < 7 then m.name = "reply"; return m, "invalid reply message (no EXT STS)" end
		m.ext_sts = u8(s, 6)
		pos = 7
		if is_dh485(m.cmd) and (m.ext_sts == 0x1A or m.ext_sts == 0x1B) then
			if #s < 8 then m.name = "reply"; return m, "invalid reply message (no owner node)" end
			m.owner = u8(s, 7)
			pos = 8
		end
	end
	m.name = command_name(m.cmd, m.has_fnc, m.fnc)
	m.body = pos
	m.data_off, m.data_len = pos, #s - pos
	if m.is_reply then return m end

	local function short() m.addr = nil; m.data_off, m.data_len = pos, #s - pos; return m, "message too short" end
	local c, f, n = m.cmd, m.fnc, #s - pos
	if c == 0x01 then
		if n < 3 then return short() end
		m.size, m.data_off = u8(s, pos + 2), pos + 3
	elseif c == 0x00 or c == 0x08 then
		if n < 2 then return short() end
		m.data_off = pos + 2
		m.size = #s - m.data_off
	elseif c == 0x06 and f == 0x01 then
		if n < 3 then return short() end
		m.size = u8(s, pos + 2)
	elseif c == 0x0F and (f == 0xA1 or f == 0xA2 or f == 0xA9 or f == 0xAA or f == 0xAB) then
		local three = f ~= 0xA1 and f ~= 0xA9
		if n < 1 then return short() end
		local nbytes = u8(s, pos)
		local file, k1 = get_field(s, pos + 1)
		if not file or pos + 1 + k1 >= #s then return short() end
		local code = u8(s, pos + 1 + k1)
		local elem, k2 = get_field(s, pos + 2 + k1)
		if not elem then return short() end
		local p = pos + 2 + k1 + k2
		local sub = 0
		if three then
			local k3
			sub, k3 = get_field(s, p)
			if not sub then return short() end
			p = p + k3
		end
		m.addr = { type = SLC_CODES[code], file = file, element = elem,
			sub = (three and sub ~= 0) and sub or nil, code = code }
		m.addr_off, m.addr_len = pos + 1, p - pos - 1
		m.size = nbytes
		m.data_off = p
		local write = f ~= 0xA1 and f ~= 0xA2
		if write and #s - p < nbytes * (f == 0xAB and 2 or 1) then return short() end
	elseif c == 0x0F and (f == 0x00 or f == 0x01 or f == 0x02 or f == 0x26 or f == 0x67 or f == 0x68) then
		local p = pos
		if f == 0x00 or f == 0x01 or f == 0x67 or f == 0x68 then
			if n < 4 then return short() end
			m.pkt_offset, m.total = le16(s, p), le16(s, p + 2)
			p = p + 4
		end
		local a, k
		if f <= 0x02 and is_plc3_addr(s, p) then
			a, k = plc3_addr(s, p)
			m.name = "PLC-3 " .. m.name
		else
			a, k = plc5_addr(s, p)
		end
		if not a then m.addr = nil; m.data_off, m.data_len = pos, #s - pos; return m, k end
		m.addr, m.addr_off, m.addr_len = a, p, k
		p = p + k
		if f == 0x68 then
			if #s < p + 2 then return short() end
			m.size = le16(s, p); p = p + 2
		elseif f == 0x01 then
			if #s < p + 1 then return short() end
			m.size = u8(s, p); p = p + 1
		elseif (f == 0x02 or f == 0x26) and #s < p + 4 then
			return short()
		end
		m.data_off = p
		if f == 0x00 then
			m.size = #s - p
		elseif f == 0x67 then
			-- the type/data parameter, then the elements
			local id, size, k2 = typedata(s, p)
			if not id then return short() end
			local count, dstart, dlen, ftid, ftsize = 1, p + k2, size, id, size
			if id == 9 then
				if #s - (p + k2) < size then return short() end
				local eid, esize, k3 = typedata(s:sub(1, p + k2 + size), p + k2)
				if not eid or eid == 9 or esize == 0 or (size - k3) % esize ~= 0 then
					m.addr = nil; m.data_off, m.data_len = pos, #s - pos
					return m, "invalid typed data"
				end
				count, dstart, dlen, ftid, ftsize = (size - k3) / esize, p + k2 + k3, size - k3, eid, esize
			elseif #s - (p + k2) < size then
				return short()
			end
			m.size, m.data_off, m.data_len = count, dstart, dlen
			m.typed_ft = typedata_file_type(ftid, ftsize)
			return m
		end
	end
	m.data_len = #s - m.data_off
	return m
end

-- Values into v from s[i, i+n) as file type ft, else the words, else raw bytes.
local function view_values(v, ft, s, i, n)
	v.ft = ft
	if n <= 0 then return end
	local vals = values_decode(ft, s, i, n)
	if (not vals or #vals == 0) and ft ~= "N" and n % 2 == 0 then
		v.ft = "N"
		vals = values_decode("N", s, i, n)
	end
	if not vals or #vals == 0 then v.raw_off, v.raw_len = i, n; return end
	v.values = vals
end

-- PLC-5 word range data: a float goes high-order word first (doc/PROTOCOL.md 5).
local function view_word_range(v, ft, s, i, n, plc3)
	if not plc3 and ft == "F" and n >= 4 and n % 4 == 0 then
		local t = {}
		for k = i, i + n - 1, 4 do
			t[#t + 1] = s:sub(k + 3, k + 4) .. s:sub(k + 1, k + 2)
		end
		local swapped = string.rep("\0", i) .. table.concat(t)
		view_values(v, ft, swapped, i, n)
		v.swapped = true
		return
	end
	view_values(v, ft, s, i, n)
end

local function single_bit(s, i, n)
	if n ~= 2 and n ~= 4 then return nil end
	local m = 0
	for k = 0, n - 1 do m = m + u8(s, i + k) * 256 ^ k end
	if m == 0 then return nil end
	local bit = 0
	while m % 2 == 0 do m = m / 2; bit = bit + 1 end
	if m ~= 1 then return nil end
	return bit
end

-- A write of one bit (0F/AB one-bit mask; 0F/26 AND FFFF OR bit or AND ~bit OR 0;
-- 0F/02 SET or RESET one bit): the bit joins the address and its value is shown.
local function view_bit_write(v, m, s)
	local a = m.addr
	if not a or a.ascii or a.bit then return end
	local d, n = m.data_off, m.data_len
	local bit, on = nil, 0
	if m.fnc == 0xAB and m.size > 0 and n == 2 * m.size then
		bit = single_bit(s, d, m.size)
		if bit then on = band(rshift(u8(s, d + m.size + math.floor(bit / 8)), bit % 8), 1) end
	elseif (m.fnc == 0x26 or m.fnc == 0x02) and n == 4 then
		local w1, w2 = le16(s, d), le16(s, d + 2)
		local b1, b2 = single_bit(s, d, 2), single_bit(s, d + 2, 2)
		if m.fnc == 0x26 then
			local inv = string.char(band(bxor(u8(s, d), 0xFF), 0xFF), band(bxor(u8(s, d + 1), 0xFF), 0xFF))
			local b0 = single_bit(inv, 0, 2)
			if w1 == 0xFFFF and b2 then bit, on = b2, 1
			elseif w2 == 0 and b0 then bit = b0 end
		elseif b1 and w2 == 0 then bit, on = b1, 1
		elseif w1 == 0 and b2 then bit = b2 end
	end
	if not bit then return end
	local b = { type = a.type, file = a.file, element = a.element, sub = a.sub, bit = bit, plc3 = a.plc3 }
	if is_tcr(b.type) and not b.sub then b.sub = 0 end
	if b.type and not addr_fields_ok(b) then return end
	v.addr_text = format_addr(b)
	v.bit_addr = b
	v.values = { { kind = "bit", bit = on, text = tostring(on) } }
	v.ft = b.type
end

local function view_command_data(v, m, s)
	local d, n = m.data_off, m.data_len
	if not d or n <= 0 then return end
	local ft = m.addr and value_file_type(m.addr) or "N"
	if m.cmd == 0x0F and m.has_fnc then
		local f = m.fnc
		if f == 0xA9 or f == 0xAA then return view_values(v, ft, s, d, n) end
		if f == 0x00 then return view_word_range(v, ft, s, d, n, m.addr and m.addr.plc3) end
		if f == 0x67 and m.typed_ft then return view_values(v, m.typed_ft, s, d, n) end
		if f == 0xAB or f == 0x26 or f == 0x02 then
			v.mask_kind = f == 0xAB and "mask/data" or (f == 0x26 and "and/or" or "set/reset")
			v.masks_off, v.masks_len = d, n
			view_bit_write(v, m, s)
			return
		end
	elseif m.cmd == 0x08 or m.cmd == 0x00 then
		return view_values(v, "N", s, d, n)
	end
	v.raw_off, v.raw_len = d, n
end

-- The diagnostic status (06/03) reply: processor type, series, revision, mode
-- (doc/PROTOCOL.md 4.9; lib/proto/pccc_diag.c), or nil.
local PROCESSORS = {
	[0x13] = "PLC-5/12", [0x14] = "PLC-5/25", [0x15] = "PLC-5/40", [0x18] = "SLC 5/01",
	[0x1A] = "SLC 500 (fixed)", [0x21] = "PLC-5/60", [0x22] = "PLC-5/10", [0x23] = "PLC-5/60",
	[0x25] = "SLC 5/02", [0x28] = "PLC-5/40L", [0x29] = "PLC-5/60L", [0x31] = "PLC-5/11",
	[0x32] = "PLC-5/20", [0x33] = "PLC-5/30", [0x49] = "SLC 5/03", [0x4A] = "PLC-5/20E",
	[0x4B] = "PLC-5/40E", [0x55] = "PLC-5/80E", [0x58] = "MicroLogix 1000", [0x59] = "PLC-5/80E",
	[0x5B] = "SLC 5/04", [0x6F] = "SLC 5/04 (L541)", [0x78] = "SLC 5/05", [0x83] = "PLC-5/30E",
	[0x86] = "PLC-5/80E", [0x88] = "MicroLogix 1200", [0x89] = "MicroLogix 1500 LSP",
	[0x8C] = "MicroLogix 1500 LRP", [0x95] = "CompactLogix L35E", [0x9C] = "MicroLogix 1100",
	[0x9F] = "MicroLogix 1400",
}
local INTERFACES = { [0x2C] = "1770-KF3", [0x5F] = "1747-KFC15" }
local SLC_MODES = { [0] = "download", [1] = "program", [3] = "idle", [6] = "run",
	[7] = "test continuous", [8] = "test single scan" }
local PLC5_MODES = { [0] = "program load", [2] = "run", [4] = "remote program", [5] = "remote test",
	[6] = "remote run" }

local function diag_status(s, i, n)
	if n < 2 then return nil end
	local kind = u8(s, i + 1)
	local t = kind == 0xEE and 3 or ((kind == 0xEB or kind == 0xFE) and 2 or 7)
	if n <= t then return nil end
	local code = u8(s, i + t)
	local d = { code = code }
	local function series(b)
		d.series = string.char(65 + band(rshift(b, 5), 7))
		d.rev = band(b, 0x1F) + 1
	end
	if kind == 0xEE then
		if n > 4 then series(u8(s, i + 4)) end
		if n > 18 then d.mode = SLC_MODES[band(u8(s, i + 18), 0x1F)] or "unknown" end
		d.name = PROCESSORS[code]
	elseif kind == 0xEB then
		d.mode = PLC5_MODES[band(u8(s, i), 7)] or "unknown"
		if n > 7 then series(u8(s, i + 7)) end
		d.name = PROCESSORS[code]
	elseif kind == 0xFE then
		d.name = INTERFACES[code]
	else
		d.name = PROCESSORS[code]
	end
	d.name = d.name or string.format("unknown (0x%02X)", code)
	local text = d.name
	if d.series then text = text .. string.format(" series %s rev %d", d.series, d.rev) end
	text = text .. string.format(" (type 0x%02X)", code)
	if d.mode then text = text .. " mode " .. d.mode end
	d.text = text
	return d
end

local function view_reply_data(v, m, s)
	local c = v.orig
	local d, n = m.data_off, m.data_len
	if not d or n <= 0 or m.sts ~= 0 then return end
	if c and c.cmd == 0x0F and c.has_fnc then
		if c.fnc == 0xA1 or c.fnc == 0xA2 then return view_values(v, c.ft, s, d, n) end
		if c.fnc == 0x01 then return view_word_range(v, c.ft, s, d, n, c.addr and c.addr.plc3) end
		if c.fnc == 0x68 then
			local k, ft = typedata_skip(s, d)
			if k and k <= n then return view_values(v, ft, s, d + k, n - k) end
		end
	elseif c and c.cmd == 0x01 then
		return view_values(v, "N", s, d, n)
	elseif c and c.cmd == 0x06 and c.fnc == 0x03 then
		v.diag = diag_status(s, d, n)
	end
	v.raw_off, v.raw_len = d, n
end

-- ---------------------------------------------------------------- transactions

-- The command a reply answers (tools/common/decode.c cmd_find): same TNS and CMD, the
-- stations swapped; else the newest with that TNS (a bridge may rewrite SRC).
local function cmd_find(ctx, m)
	local best
	for _, c in ipairs(ctx.cmds) do
		if c.tns == m.tns and bor(c.cmd, 0x40) == m.cmd then
			if c.dst == m.src and c.src == m.dst then return c end
			if not best or c.age > best.age then best = c end
		end
	end
	return best
end

local function cmd_remember(ctx, m, v, sym)
	local slot
	for _, c in ipairs(ctx.cmds) do
		if c.tns == m.tns and c.dst == m.dst and c.src == m.src then slot = c; break end
	end
	if not slot then
		if #ctx.cmds < DECODE_CMDS then
			slot = {}
			ctx.cmds[#ctx.cmds + 1] = slot
		else
			slot = ctx.cmds[1]
			for _, c in ipairs(ctx.cmds) do if c.age < slot.age then slot = c end end
		end
	end
	for k in pairs(slot) do slot[k] = nil end
	ctx.clock = ctx.clock + 1
	slot.dst, slot.src, slot.cmd, slot.fnc, slot.has_fnc, slot.tns = m.dst, m.src, m.cmd, m.fnc,
		m.has_fnc, m.tns
	slot.label = v.name
	slot.addr = v.bit_addr or m.addr
	slot.size = m.size
	slot.ft = m.addr and value_file_type(m.addr) or "N"
	slot.age = ctx.clock
	slot.sym = sym
end

local function build_view(ctx, sym, remember)
	local s = sym.data
	local v = { size = -1 }
	local m, err = msg_decode(s)
	v.m = m
	if err and #s < 6 then v.error = err; return v end
	v.ok = true
	v.name = m.name
	if err then v.error = err end
	if not m.is_reply then
		v.cmdtext = m.has_fnc and string.format("%02X/%02X", m.cmd, m.fnc) or string.format("%02X", m.cmd)
		if m.addr then
			v.addr_text = format_addr(m.addr)
		elseif (m.cmd == 0x01 or m.cmd == 0x08 or m.cmd == 0x00) and #s >= 8 then
			v.addr_text = string.format("byte 0x%04X", le16(s, 6))
			v.plc2_addr = true
		end
		v.size = m.size
		if not err then
			view_command_data(v, m, s)
			if remember then cmd_remember(ctx, m, v, sym) end
		elseif m.data_len and m.data_len > 0 then
			v.raw_off, v.raw_len = m.data_off, m.data_len
		end
		return v
	end
	v.cmdtext = string.format("%02X", m.cmd)
	v.has_sts = true
	v.orig = cmd_find(ctx, m)
	if v.orig then
		local o = v.orig
		v.name = o.has_fnc and string.format("reply to %02X/%02X", o.cmd, o.fnc) or
			string.format("reply to %02X", o.cmd)
		if o.addr then v.addr_text = format_addr(o.addr); v.size = o.size end
	else
		v.name = "reply"
	end
	v.bad_reply = err ~= nil
	if not err then view_reply_data(v, m, s) end
	return v
end

-- ---------------------------------------------------------------- the frame decoder

-- A port of lib/proto/frame.c's byte-fed decoder (its rules are in frame.h).
-- Each symbol also gets its span [s, e] in stream offsets.
local ST = { IDLE = 0, EOT_TRAILER = 1, DLE = 2, POLL_STN = 3, POLL_STN_DLE = 4, POLL_BCC = 5,
	APOLL_STN = 6, APOLL_STN_DLE = 7, APOLL_BCC = 8, SOH_STN = 9, SOH_STN_DLE = 10, SOH_DLE = 11,
	SOH_STX = 12, DATA = 13, DATA_DLE = 14, CHECK = 15 }

local Decoder = {}
Decoder.__index = Decoder

-- duplex "radio": full duplex without embedded responses (a radio modem sends
-- no ACK or NAK: a DLE pair inside a frame breaks it, doc/PROTOCOL.md 2.6)
local function decoder_new(check, duplex, bcc_stx)
	local d = setmetatable({ check = check, half = duplex == "half", auto = duplex == "auto",
		no_embedded = duplex == "radio", bcc_stx = bcc_stx }, Decoder)
	d:reset()
	return d
end

function Decoder:reset()
	self.locked = self.check == "bcc" and "bcc" or "crc"
	self.auto_locked = false
	self.state = ST.IDLE
	self.in_master, self.stn, self.nchk, self.chk = false, 0, 0, {}
	self.overflow, self.sum, self.crc, self.len, self.buf = false, 0, 0, 0, {}
	self.start = 0
end

function Decoder:busy()
	return self.state ~= ST.IDLE and self.state ~= ST.EOT_TRAILER
end

function Decoder:begin_frame(master, start)
	self.in_master, self.stn, self.len, self.buf = master, 0, 0, {}
	self.overflow, self.sum, self.crc, self.nchk, self.chk = false, 0, 0, 0, {}
	self.start = start
	self.state = master and ST.SOH_STN or ST.DATA
end

function Decoder:data_byte(b)
	if self.len < MAX_DATA then
		self.len = self.len + 1
		self.buf[self.len] = b
	else
		self.overflow = true
	end
	self.sum = (self.sum + b) % 256
	self.crc = crc_step(self.crc, b)
end

function Decoder:frame_fields(sym)
	sym.master = self.in_master
	sym.has_station = self.in_master and self.state ~= ST.SOH_STN and self.state ~= ST.SOH_STN_DLE
	sym.station = sym.has_station and self.stn or nil
	local c = {}
	for i = 1, self.len do c[i] = string.char(self.buf[i]) end
	sym.data = table.concat(c)
end

function Decoder:symbol_error(sym, id, bad, keep, in_frame, o)
	sym.kind, sym.error, sym.bad_byte = "ERROR", id, bad
	if in_frame then self:frame_fields(sym) end
	sym.s, sym.e = self.start, o - keep
	self.state = ST.IDLE
	return true
end

function Decoder:restart(sym, id, b, in_frame, o)
	self:symbol_error(sym, id, id == ID_INVALID_SYMBOL and b or 0, 2, in_frame, o)
	self:begin_frame(b == SOH, o - 1)
	return true
end

function Decoder:simple(sym, kind, o)
	sym.kind, sym.s, sym.e = kind, self.start, o
	self.state = ST.IDLE
	return true
end

function Decoder:frame_done(sym, used, expected, actual, e)
	self:frame_fields(sym)
	sym.check, sym.expected, sym.actual = used, expected, actual
	sym.check_ok = expected == actual
	sym.s, sym.e = self.start, e
	if self.overflow then sym.kind, sym.error = "ERROR", ID_TOO_LONG
	elseif self.len < MIN_DATA then sym.kind, sym.error = "ERROR", ID_TOO_SHORT
	else sym.kind = "FRAME" end
	self.state = ST.IDLE
	return true
end

-- returns done, to_next
function Decoder:check_byte(sym, b, o)
	self.nchk = self.nchk + 1
	self.chk[self.nchk] = b
	local mode = self.check
	if mode == "auto" and self.auto_locked and self.locked == "crc" then mode = "crc" end
	local bccx = (256 - self.sum) % 256
	if mode == "bcc" then return self:frame_done(sym, "BCC", bccx, b, o) end
	if mode == "crc" then
		if self.nchk < 2 then return false end
		return self:frame_done(sym, "CRC", self.crc, self.chk[1] + 256 * self.chk[2], o)
	end
	if self.nchk == 1 then
		if b ~= bccx then return false end
		self.locked, self.auto_locked = "bcc", true
		return self:frame_done(sym, "BCC", bccx, b, o)
	end
	local got = self.chk[1] + 256 * self.chk[2]
	if got == self.crc then
		self.locked, self.auto_locked = "crc", true
		return self:frame_done(sym, "CRC", self.crc, got, o)
	end
	if b == DLE or self.auto_locked then
		-- the second byte is not part of this frame
		self:frame_done(sym, "BCC", bccx, self.chk[1], o - 1)
		return true, b == DLE
	end
	return self:frame_done(sym, "CRC", self.crc, got, o)
end

local function is_nak(b) return b == NAK or b == NAK_OLD end

function Decoder:after_dle(sym, b, o)
	if b == STX then self:begin_frame(false, self.start); return false end
	if b == SOH then self:begin_frame(true, self.start); return false end
	if b == ENQ then
		if self.half then self.state = ST.POLL_STN; return false end
		if self.auto then self.state = ST.APOLL_STN; return false end
		return self:simple(sym, "ENQ", o)
	end
	if b == EOT then return self:simple(sym, "EOT", o) end
	if b == ACK then return self:simple(sym, "ACK", o) end
	if b == DLE then self.start = o; return false end      -- noise; this DLE may start a symbol
	if b == ETX then self.state = ST.IDLE; return false end -- the end of a frame we missed
	if is_nak(b) then return self:simple(sym, "NAK", o) end
	return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, false, o)
end

function Decoder:data_dle(sym, b, o)
	if b == DLE then self:data_byte(DLE); self.state = ST.DATA; return false end
	if b == ETX then
		self.crc = crc_step(self.crc, ETX)
		self.nchk, self.chk = 0, {}
		self.state = ST.CHECK
		return false
	end
	if (b == ACK or is_nak(b)) and not self.no_embedded then
		-- embedded response (doc/PROTOCOL.md 1.8): out of band, the frame goes on
		sym.kind, sym.embedded, sym.s, sym.e = b == ACK and "ACK" or "NAK", true, o - 1, o
		self.state = ST.DATA
		return true
	end
	if b == STX or b == SOH then return self:restart(sym, ID_NO_ETX, b, true, o) end
	return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, true, o)
end

function Decoder:poll_bcc(sym, b, o)
	sym.has_station, sym.station = true, self.stn
	sym.check, sym.expected, sym.actual = "BCC", (256 - self.stn) % 256, b
	sym.check_ok = sym.expected == b
	if sym.check_ok then return self:simple(sym, "POLL", o) end
	self:simple(sym, "ERROR", o)
	sym.error = ID_ERR_BAD_BCC
	return true
end

-- Auto duplex: DLE ENQ was not a poll; the deciding byte is fed again (keep).
function Decoder:auto_enq(sym, state, o)
	sym.kind, sym.s, sym.e = "ENQ", self.start, self.start + 1
	self.state = state
	if state == ST.DLE then self.start = o - 1 end
	return true, false, true
end

-- One byte at stream offset o: done, to_next, keep.
function Decoder:step(sym, b, o)
	local st = self.state
	if st == ST.IDLE or st == ST.EOT_TRAILER then
		if b == DLE then self.state, self.start = ST.DLE, o
		elseif st == ST.EOT_TRAILER then self.state = ST.IDLE end
		return false
	end
	if st == ST.DLE then return self:after_dle(sym, b, o) end
	if st == ST.POLL_STN then
		if b == DLE then self.state = ST.POLL_STN_DLE else self.stn, self.state = b, ST.POLL_BCC end
		return false
	end
	if st == ST.POLL_STN_DLE then
		if b ~= DLE then
			if b == STX or b == SOH then return self:restart(sym, ID_INVALID_SYMBOL, b, false, o) end
			return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, false, o)
		end
		self.stn, self.state = DLE, ST.POLL_BCC
		return false
	end
	if st == ST.POLL_BCC then return self:poll_bcc(sym, b, o) end
	if st == ST.APOLL_STN then
		if b == DLE then self.state = ST.APOLL_STN_DLE else self.stn, self.state = b, ST.APOLL_BCC end
		return false
	end
	if st == ST.APOLL_STN_DLE then
		if b ~= DLE then return self:auto_enq(sym, ST.DLE, o) end
		self.stn, self.state = DLE, ST.APOLL_BCC
		return false
	end
	if st == ST.APOLL_BCC then
		if b == (256 - self.stn) % 256 then return self:poll_bcc(sym, b, o) end
		return self:auto_enq(sym, self.stn == DLE and ST.DLE or ST.IDLE, o)
	end
	if st == ST.SOH_STN then
		if b == DLE then self.state = ST.SOH_STN_DLE
		else self.stn, self.sum, self.crc, self.state = b, b, crc_step(0, b), ST.SOH_DLE end
		return false
	end
	if st == ST.SOH_STN_DLE then
		if b == DLE then
			self.stn, self.sum, self.crc, self.state = DLE, DLE, crc_step(0, DLE), ST.SOH_DLE
			return false
		end
		if b == STX or b == SOH then return self:restart(sym, ID_NO_ETX, b, true, o) end
		return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, true, o)
	end
	if st == ST.SOH_DLE then
		if b == DLE then self.state = ST.SOH_STX; return false end
		return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, true, o)
	end
	if st == ST.SOH_STX then
		if b == STX then
			self.crc = crc_step(self.crc, STX)
			if self.bcc_stx then self.sum = (self.sum + STX) % 256 end
			self.state = ST.DATA
			return false
		end
		if b == SOH then return self:restart(sym, ID_NO_ETX, b, true, o) end
		return self:symbol_error(sym, ID_INVALID_SYMBOL, b, 0, true, o)
	end
	if st == ST.DATA then
		if b == DLE then self.state = ST.DATA_DLE else self:data_byte(b) end
		return false
	end
	if st == ST.DATA_DLE then return self:data_dle(sym, b, o) end
	if st == ST.CHECK then return self:check_byte(sym, b, o) end
	self.state = ST.IDLE
	return false
end


-- ---------------------------------------------------------------- fields

local f = df1.fields
f.symbol = ProtoField.string("df1.symbol", "Symbol")
f.dir = ProtoField.string("df1.dir", "Direction")
f.bytes = ProtoField.bytes("df1.bytes", "Wire bytes")
f.embedded = ProtoField.bool("df1.embedded", "Embedded in a frame")
f.master = ProtoField.bool("df1.master", "Half-duplex master message")
f.stn = ProtoField.uint8("df1.stn", "Station (STN)", base.DEC)
f.dst = ProtoField.uint8("df1.dst", "Destination (DST)", base.DEC)
f.src = ProtoField.uint8("df1.src", "Source (SRC)", base.DEC)
f.cmd = ProtoField.uint8("df1.cmd", "Command (CMD)", base.HEX)
f.reply = ProtoField.bool("df1.reply", "Reply")
f.fnc = ProtoField.uint8("df1.fnc", "Function (FNC)", base.HEX)
f.name = ProtoField.string("df1.name", "Name")
f.sts = ProtoField.uint8("df1.sts", "Status (STS)", base.HEX)
f.sts_text = ProtoField.string("df1.sts_text", "Status text")
f.ext_sts = ProtoField.uint8("df1.ext_sts", "Extended status (EXT STS)", base.HEX)
f.ext_sts_text = ProtoField.string("df1.ext_sts_text", "Extended status text")
f.owner = ProtoField.uint8("df1.owner", "Owner node", base.DEC)
f.tns = ProtoField.uint16("df1.tns", "Transaction (TNS)", base.HEX)
f.addr = ProtoField.string("df1.addr", "Address")
f.file_type = ProtoField.string("df1.file_type", "File type")
f.file = ProtoField.uint16("df1.file", "File", base.DEC)
f.element = ProtoField.uint16("df1.element", "Element", base.DEC)
f.subelement = ProtoField.uint16("df1.subelement", "Sub-element", base.DEC)
f.bit = ProtoField.uint8("df1.bit", "Bit", base.DEC)
f.size = ProtoField.int32("df1.size", "Size")
f.pkt_offset = ProtoField.uint16("df1.pkt_offset", "Packet offset (words)", base.DEC)
f.total = ProtoField.uint16("df1.total", "Total transaction", base.DEC)
f.value = ProtoField.string("df1.value", "Value")
f.int = ProtoField.int32("df1.value.int", "Integer")
f.float = ProtoField.float("df1.value.float", "Float")
f.string = ProtoField.string("df1.value.string", "String")
f.tcr_ctl = ProtoField.uint16("df1.tcr.ctl", "Control word", base.HEX)
f.tcr_pre = ProtoField.int16("df1.tcr.pre", "PRE / LEN")
f.tcr_acc = ProtoField.int16("df1.tcr.acc", "ACC / POS")
f.mask = ProtoField.bytes("df1.mask", "Mask")
f.mask_data = ProtoField.bytes("df1.mask_data", "Mask data")
f.mode = ProtoField.uint8("df1.mode", "Mode", base.HEX)
f.data = ProtoField.bytes("df1.data", "Data")
f.processor = ProtoField.string("df1.processor", "Processor")
f.processor_type = ProtoField.uint8("df1.processor_type", "Processor type", base.HEX)
f.check = ProtoField.string("df1.check", "Error check")
f.check_ok = ProtoField.bool("df1.check_ok", "Check good")
f.bcc = ProtoField.uint8("df1.bcc", "BCC", base.HEX)
f.crc = ProtoField.uint16("df1.crc", "CRC", base.HEX)
f.check_expected = ProtoField.uint16("df1.check_expected", "Expected check", base.HEX)
f.error_id = ProtoField.uint16("df1.error_id", "Catalog ID", base.DEC)
f.error = ProtoField.string("df1.error", "Error")
f.enq_retry = ProtoField.uint8("df1.enq_retry", "ENQ retry", base.DEC)
f.enq_for = ProtoField.framenum("df1.enq_for", "Frame not acknowledged")
f.request_in = ProtoField.framenum("df1.request_in", "Request in", base.NONE, frametype.REQUEST)
f.response_in = ProtoField.framenum("df1.response_in", "Response in", base.NONE, frametype.RESPONSE)
f.response_time = ProtoField.relative_time("df1.response_time", "Response time")
f.duplicate_of = ProtoField.framenum("df1.duplicate_of", "Duplicate of")
f.relay_of = ProtoField.framenum("df1.relay_of", "Relayed copy of")
f.radio_repeat = ProtoField.framenum("df1.radio_repeat", "Sent again by its sender, first in")
f.radio_duplicate = ProtoField.bool("df1.radio_duplicate", "Radio duplicate (a node drops it)")
f.fragment = ProtoField.framenum("df1.fragment", "Record with part of this symbol")
f.reassembled_in = ProtoField.framenum("df1.reassembled_in", "Completed in")

local ex = {
	bad_check = ProtoExpert.new("df1.expert.bad_check", "Bad BCC/CRC", expert.group.CHECKSUM,
		expert.severity.ERROR),
	nak = ProtoExpert.new("df1.expert.nak", "NAK", expert.group.SEQUENCE, expert.severity.WARN),
	enq = ProtoExpert.new("df1.expert.enq_retry", "ENQ retry", expert.group.SEQUENCE,
		expert.severity.NOTE),
	duplicate = ProtoExpert.new("df1.expert.duplicate", "Duplicate message", expert.group.SEQUENCE,
		expert.severity.WARN),
	stale = ProtoExpert.new("df1.expert.stale", "Stale reply", expert.group.SEQUENCE,
		expert.severity.WARN),
	unmatched = ProtoExpert.new("df1.expert.unmatched", "Reply to no command seen",
		expert.group.SEQUENCE, expert.severity.NOTE),
	plc_error = ProtoExpert.new("df1.expert.plc_error", "PLC error status", expert.group.RESPONSE_CODE,
		expert.severity.WARN),
	malformed = ProtoExpert.new("df1.expert.malformed", "Malformed DF1", expert.group.MALFORMED,
		expert.severity.ERROR),
	incomplete = ProtoExpert.new("df1.expert.incomplete", "Incomplete DF1 symbol",
		expert.group.MALFORMED, expert.severity.WARN),
	relayed = ProtoExpert.new("df1.expert.relayed", "Radio modem: relayed copy", expert.group.SEQUENCE,
		expert.severity.NOTE),
}
df1.experts = { ex.bad_check, ex.nak, ex.enq, ex.duplicate, ex.stale, ex.unmatched, ex.plc_error,
	ex.malformed, ex.incomplete, ex.relayed }

-- ---------------------------------------------------------------- preferences

df1.prefs.rtac = Pref.bool("Dissect RTAC serial records as DF1", true,
	"Link type 250 (RTAC serial) records are DF1 at once; off: Wireshark's RTAC serial dissector " ..
	"alone, and DF1 through Decode As (RTAC Serial Data)")
df1.prefs.tcp_port = Pref.uint("Raw DF1 TCP port", 0,
	"Raw DF1 over TCP to a serial device server on this port (0: off; Decode As works too)")
df1.prefs.check = Pref.enum("Error check", 0,
	"BCC or CRC; auto decides per direction from the first good frame, as df1mon does",
	{ { 1, "Auto", 0 }, { 2, "BCC", 1 }, { 3, "CRC", 2 } }, false)
df1.prefs.duplex = Pref.enum("Duplex", 0,
	"Auto: DLE ENQ followed by STN and its BCC is a half-duplex poll, else the full-duplex ENQ",
	{ { 1, "Auto", 0 }, { 2, "Full duplex", 1 }, { 3, "Half duplex", 2 } }, false)
df1.prefs.link = Pref.enum("Link mode", 0,
	"Radio modem (DF1 Radio Modem, doc/PROTOCOL.md 2.6): full-duplex frames, no ACK, NAK, ENQ or " ..
	"poll expected; a packet heard again unchanged (DST SRC CMD STS TNS among the last 20) is a " ..
	"store-and-forward relay's copy. The Duplex preference is then not used",
	{ { 1, "Point to point (full or half duplex)", 0 }, { 2, "Radio modem", 1 } }, false)
df1.prefs.bcc_stx = Pref.bool("Half-duplex master BCC includes STX", false,
	"The manual's text sums STN and data only (doc/PROTOCOL.md 2.2); some devices add STX")

local CHECKS = { [0] = "auto", [1] = "bcc", [2] = "crc" }
local DUPLEX = { [0] = "auto", [1] = "full", [2] = "half" }

-- ---------------------------------------------------------------- capture state

-- G.streams: one decoder per direction (RTAC event type, or TCP stream and side);
-- G.ctxs: the command memory (by TNS) of the capture or of one TCP stream;
-- G.recs[frame]: the symbols a record completes and the parts it holds of others.
local G

local function state_reset()
	G = { streams = {}, ctxs = {}, recs = {}, nsym = 0, finished = false, now = 0, radio = {} }
end

local RADIO_DEPTH = 20   -- a radio node's duplicate detection remembers 20 packets
local function radio_mode() return df1.prefs.link == 1 end
state_reset()

local function get_rec(n)
	local r = G.recs[n]
	if not r then r = { syms = {}, parts = {} }; G.recs[n] = r end
	return r
end

local function get_stream(key, ctxkey, dir)
	local s = G.streams[key]
	if not s then
		s = { key = key, dir = dir, dec = decoder_new(CHECKS[df1.prefs.check] or "auto",
			radio_mode() and "radio" or DUPLEX[df1.prefs.duplex] or "auto", df1.prefs.bcc_stx),
			off = 0, lo = 0, bytes = {}, fr = {}, pos = {}, enq = 0, last_cmds = {} }
		G.ctxs[ctxkey] = G.ctxs[ctxkey] or { cmds = {}, clock = 0 }
		s.ctx = G.ctxs[ctxkey]
		G.streams[key] = s
		G.streams[#G.streams + 1] = s
	end
	return s
end

-- Radio modem: a good packet whose DST SRC CMD STS TNS repeats one of the last
-- RADIO_DEPTH (as tools/df1mon/mon_radio.c): a relay's copy of the first
-- (sym.relay_of); a further copy, or the tx side sending its own packet again
-- (sym.repeat_of), is what a node's duplicate detection drops (radio_dup).
-- true when the packet is such a copy.
local function radio_copy(st, sym)
	local d = sym.data
	local key = d:sub(1, 6)
	for _, p in ipairs(G.radio) do
		if p.key == key then
			if st.dir == "tx" and p.dir == "tx" then
				sym.repeat_of, sym.radio_dup = p.sym, true
			else
				sym.relay_of, sym.radio_dup = p.sym, p.relayed
				p.relayed = true
			end
			return true
		end
	end
	if #G.radio >= RADIO_DEPTH then table.remove(G.radio, 1) end
	G.radio[#G.radio + 1] = { key = key, dir = st.dir, sym = sym }
	return false
end

-- What the first pass learns about a symbol (in the order df1mon prints them).
local function analyse(st, sym)
	sym.time = G.now
	if sym.kind == "FRAME" then
		-- radio modem: a relayed copy is neither a new command (its reply
		-- answers the first) nor a second reply
		local copy = radio_mode() and sym.check_ok and #sym.data >= 6 and radio_copy(st, sym)
		-- a decoding bug must not lose the symbol: it is shown with the error
		local okv, v = pcall(build_view, st.ctx, sym, sym.check_ok and not copy)
		if not okv then v = { size = -1, error = "dissector error: " .. tostring(v), m = {} } end
		sym.view = v
		st.enq = 0
		st.last_frame = sym
		if not sym.check_ok or not v.ok or copy then return end
		local m = v.m
		if not m.is_reply then
			local last = st.last_cmds[m.src]
			-- the same SRC, CMD and TNS again: the receiver ACKs and discards it (doc/PROTOCOL.md 1.7)
			if last and last.cmd == m.cmd and last.tns == m.tns then
				sym.duplicate_of = last.sym
			else
				st.last_cmds[m.src] = { cmd = m.cmd, tns = m.tns, sym = sym }
			end
			return
		end
		local c = v.orig
		if not c or not c.sym then sym.unmatched = true; return end
		sym.request = c.sym
		if not c.sym.response then
			c.sym.response = sym
			sym.rtt = sym.time - c.sym.time
		elseif c.age ~= st.ctx.clock then
			sym.stale = true            -- a newer command went out since it was answered
		else
			sym.duplicate_of = c.sym.response
		end
	elseif sym.kind == "ENQ" and not sym.embedded and not radio_mode() then
		st.enq = st.enq + 1
		sym.enq_no = st.enq
		sym.enq_for = st.last_frame
	end
end

local function emit(st, sym)
	G.nsym = G.nsym + 1
	sym.id, sym.dir = G.nsym, st.dir
	local w, pieces = {}, {}
	for o = sym.s, sym.e do
		local fr = st.fr[o]
		if fr then
			w[#w + 1] = string.char(st.bytes[o])
			local last = pieces[#pieces]
			if last and last.frame == fr then last.len = last.len + 1
			else pieces[#pieces + 1] = { frame = fr, pos = st.pos[o], len = 1 } end
		end
	end
	if #pieces == 0 then return end
	sym.wire, sym.pieces = table.concat(w), pieces
	sym.frame = pieces[#pieces].frame
	analyse(st, sym)
	local r = get_rec(sym.frame)
	r.syms[#r.syms + 1] = sym
	for i = 1, #pieces - 1 do
		local p = pieces[i]
		local pr = get_rec(p.frame)
		pr.parts[#pr.parts + 1] = { sym = sym, pos = p.pos, len = p.len }
	end
end

-- Forget the bytes no symbol can still need.
local function trim(st, upto)
	for o = st.lo, upto - 1 do st.bytes[o], st.fr[o], st.pos[o] = nil, nil, nil end
	if upto > st.lo then st.lo = upto end
end

local function feed(st, b, frame, pos)
	local o = st.off
	st.off = o + 1
	st.bytes[o], st.fr[o], st.pos[o] = b, frame, pos
	local dec = st.dec
	while true do
		local sym = {}
		local done, to_next, keep = dec:step(sym, b, o)
		if not done then break end
		if to_next then dec.state, dec.start = ST.DLE, o end
		emit(st, sym)
		if not keep then break end
	end
	trim(st, dec:busy() and dec.start or o + 1)
end

-- The end of the capture (tools/df1mon/mon_stream.c stream_finish): DLE STX fed after
-- the last byte settles a frame waiting for its check and ends one under way.
local function finish(st)
	local dec, real_end = st.dec, st.off - 1
	for _, b in ipairs({ DLE, STX }) do
		local o = st.off
		st.off = o + 1
		st.bytes[o] = b
		local sym, done, to_next, keep
		repeat
			sym = {}
			done, to_next, keep = dec:step(sym, b, o)
			if done and keep then emit(st, sym) end
		until not (done and keep)
		if done then
			if (b == DLE and sym.kind == "FRAME" and dec.check == "auto" and sym.check == "BCC" and
				not sym.check_ok) or (b == STX and sym.kind == "ERROR" and sym.error == ID_NO_ETX) then
				emit(st, sym)
			else
				local s = math.min(sym.s or real_end, real_end)
				emit(st, { kind = "ERROR", error = ID_NO_ETX, cut = true, s = s, e = real_end,
					data = sym.data })
			end
			break
		end
	end
	dec:reset()
end

-- ---------------------------------------------------------------- display

local ERROR_TEXT = {
	[ID_ERR_BAD_BCC] = "poll with wrong BCC",
	[ID_TOO_LONG] = "received message too long",
	[ID_TOO_SHORT] = "received message too short",
	[ID_NO_ETX] = "incomplete message, no ETX received",
}

local function error_text(sym)
	if sym.cut then return "input ended inside a symbol" end
	if sym.error == ID_INVALID_SYMBOL then
		return string.format("invalid symbol received after DLE (0x%02X)", sym.bad_byte or 0)
	end
	return ERROR_TEXT[sym.error] or "malformed input"
end

local function check_text(sym)
	if sym.check_ok then return sym.check .. " ok" end
	local fmt = sym.check == "BCC" and "0x%02X" or "0x%04X"
	return string.format("%s bad expected " .. fmt .. " actual " .. fmt, sym.check, sym.expected,
		sym.actual)
end

local function values_text(v)
	if not v.values then return nil end
	local t = {}
	for i, x in ipairs(v.values) do
		t[i] = x.kind == "string" and ('"' .. x.text .. '"') or (x.kind == "tcr" and ("{" .. x.text .. "}") or x.text)
	end
	return table.concat(t, " ")
end

-- One line, as df1mon prints it (without its columns).
local function summary(sym)
	if sym.kind == "POLL" then return string.format("POLL stn %d", sym.station) end
	if sym.kind == "ERROR" then
		return string.format("ERROR [%d] %s: %s", sym.error, ID_NAMES[sym.error] or "", error_text(sym))
	end
	if sym.kind ~= "FRAME" then return sym.kind .. (sym.embedded and " (embedded)" or "") end
	local v, t = sym.view, {}
	if not sym.check_ok then t[#t + 1] = "[" .. check_text(sym) .. "]" end
	if not v.ok then t[#t + 1] = "error: " .. (v.error or "?"); return table.concat(t, " ") end
	t[#t + 1] = v.cmdtext
	t[#t + 1] = v.name
	if v.addr_text then t[#t + 1] = v.addr_text .. (v.size >= 0 and (" size " .. v.size) or "") end
	if v.has_sts and v.m.sts ~= 0 then t[#t + 1] = string.format("STS 0x%02X", v.m.sts) end
	if v.m.ext_sts then t[#t + 1] = string.format("EXT STS 0x%02X", v.m.ext_sts) end
	local vt = values_text(v)
	if vt then t[#t + 1] = "= " .. vt end
	if v.diag then t[#t + 1] = v.diag.text end
	t[#t + 1] = string.format("tns 0x%04X", v.m.tns)
	if sym.master and sym.has_station then t[#t + 1] = "(stn " .. sym.station .. ")" end
	if radio_mode() then
		t[#t + 1] = string.format("%d > %d", v.m.src, v.m.dst)
		local first = sym.relay_of or sym.repeat_of
		if first then
			t[#t + 1] = string.format("[%s of frame %d%s]", sym.relay_of and "relay" or "repeat",
				first.frame, sym.radio_dup and ", duplicate" or "")
		end
	end
	return table.concat(t, " ")
end

local function ns_time(secs)
	local ns = math.floor(secs * 1e9 + 0.5)
	return NSTime.new(math.floor(ns / 1e9), ns % 1e9)
end

-- The frame's fields, on `at` (the app bytes: the record itself, or a new data
-- source holding them unstuffed).
local function add_frame_fields(t, sym, at, base)
	local v, s = sym.view, sym.data
	local m = v.m
	local function r(off, len)
		if off and len and len > 0 and off + len <= #s then return at(base + off, len) end
		return at(base, math.max(0, math.min(#s, 1)))
	end
	if not v.ok then
		t:add(f.error, r(0, #s), v.error)
		return
	end
	t:add(f.dst, r(0, 1), m.dst)
	t:add(f.src, r(1, 1), m.src)
	local cmd_label = m.is_reply and "reply" or
		(m.cmd == 0x0F and "command, FNC follows" or (m.cmd == 0x06 and "diagnostic, FNC follows" or m.name))
	t:add(f.cmd, r(2, 1), m.cmd):append_text(" (" .. cmd_label .. ")")
	t:add(f.reply, r(2, 1), m.is_reply):set_generated()
	t:add(f.sts, r(3, 1), m.sts):append_text(" (" .. sts_text(m.sts) .. ")")
	if m.is_reply then t:add(f.sts_text, r(3, 1), sts_text(m.sts)):set_generated() end
	t:add_le(f.tns, r(4, 2), m.tns)
	if m.has_fnc then t:add(f.fnc, r(6, 1), m.fnc):append_text(" (" .. m.name .. ")") end
	t:add(f.name, r(2, m.has_fnc and 5 or 1), v.name):set_generated()
	if m.ext_sts then
		local et = ext_sts_text(m.cmd, m.ext_sts)
		t:add(f.ext_sts, r(6, 1), m.ext_sts):append_text(" (" .. et .. ")")
		t:add(f.ext_sts_text, r(6, 1), et):set_generated()
		if m.owner then t:add(f.owner, r(7, 1), m.owner) end
		t:add_proto_expert_info(ex.plc_error, string.format("STS 0x%02X: %s; EXT STS 0x%02X: %s",
			m.sts, sts_text(m.sts), m.ext_sts, et))
	elseif m.is_reply and m.sts ~= 0 then
		t:add_proto_expert_info(ex.plc_error, string.format("STS 0x%02X: %s", m.sts, sts_text(m.sts)))
	end
	if m.pkt_offset then
		t:add_le(f.pkt_offset, r(m.body, 2), m.pkt_offset)
		t:add_le(f.total, r(m.body + 2, 2), m.total)
	end
	if v.addr_text then
		local a = v.bit_addr or m.addr or (v.orig and v.orig.addr)
		local ai = t:add(f.addr, r(m.addr_off, m.addr_len), v.addr_text)
		if m.is_reply or v.bit_addr then ai:set_generated() end
		if a then
			if a.type then ai:add(f.file_type, r(m.addr_off, m.addr_len), a.type):set_generated() end
			if a.file and a.file >= 0 then ai:add(f.file, r(m.addr_off, m.addr_len), a.file):set_generated() end
			if a.element and a.element >= 0 then
				ai:add(f.element, r(m.addr_off, m.addr_len), a.element):set_generated()
			end
			if a.sub then ai:add(f.subelement, r(m.addr_off, m.addr_len), a.sub):set_generated() end
			if a.bit then ai:add(f.bit, r(m.addr_off, m.addr_len), a.bit):set_generated() end
		end
	end
	if v.size >= 0 then
		t:add(f.size, r(m.addr_off, m.addr_len), v.size):set_generated()
	end
	if not m.is_reply and m.cmd == 0x0F and (m.fnc == 0x80 or m.fnc == 0x3A) and #s > 7 then
		t:add(f.mode, r(7, 1), u8(s, 7))
	end
	if v.values then
		for _, x in ipairs(v.values) do
			local range = x.off and r(x.off, x.len) or r(m.data_off, m.data_len)
			local vi = t:add(f.value, range, x.text)
			if x.kind == "int16" or x.kind == "int32" then vi:add(f.int, range, x.int)
			elseif x.kind == "float" then vi:add(f.float, range, x.float)
			elseif x.kind == "string" then vi:add(f.string, range, x.string)
			elseif x.kind == "tcr" then
				vi:add(f.tcr_ctl, range, x.ctl)
				vi:add(f.tcr_pre, range, x.pre)
				vi:add(f.tcr_acc, range, x.acc)
			end
			if v.swapped then vi:append_text(" (words swapped)") end
		end
	end
	if v.masks_off then
		local half = v.masks_len / 2
		if m.fnc == 0xAB and v.masks_len % 2 == 0 then
			t:add(f.mask, r(v.masks_off, half)):append_text(" (mask)")
			t:add(f.mask_data, r(v.masks_off + half, half)):append_text(" (data)")
		else
			local names = m.fnc == 0x26 and { "AND", "OR" } or { "SET", "RESET" }
			t:add(f.mask, r(v.masks_off, 2)):append_text(" (" .. names[1] .. ")")
			t:add(f.mask_data, r(v.masks_off + 2, 2)):append_text(" (" .. names[2] .. ")")
		end
	end
	if v.raw_off then
		local di = t:add(f.data, r(v.raw_off, v.raw_len))
		if v.diag then
			di:add(f.processor, r(v.raw_off, v.raw_len), v.diag.text):set_generated()
			di:add(f.processor_type, r(v.raw_off, v.raw_len), v.diag.code):set_generated()
		end
	end
	if v.error then
		t:add(f.error, r(0, #s), v.error)
		t:add_proto_expert_info(ex.malformed, v.error)
	end
end

-- Transaction links, duplicates, retries.
local function add_tracking(t, sym)
	local v = sym.view
	if sym.relay_of or sym.repeat_of then
		local first = sym.relay_of or sym.repeat_of
		t:add(sym.relay_of and f.relay_of or f.radio_repeat, first.frame):set_generated()
		t:add(f.radio_duplicate, sym.radio_dup):set_generated()
		t:add_proto_expert_info(ex.relayed, sym.relay_of and
			string.format("Relayed copy of frame %d (store and forward, unchanged)%s", first.frame,
				sym.radio_dup and "; a node that took a copy drops it (duplicate detection)" or "") or
			string.format("Sent again by its sender (application retry) as in frame %d; a node with " ..
				"duplicate detection drops it", first.frame))
	end
	if sym.duplicate_of then
		t:add(f.duplicate_of, sym.duplicate_of.frame):set_generated()
		t:add_proto_expert_info(ex.duplicate, v.m.is_reply and
			string.format("Duplicate reply (TNS 0x%04X already answered in frame %d)", v.m.tns,
				sym.duplicate_of.frame) or
			string.format("Duplicate command: same SRC, CMD and TNS as frame %d (the receiver ACKs and discards it)",
				sym.duplicate_of.frame))
	end
	if v and v.ok and not v.m.is_reply and sym.response then
		t:add(f.response_in, sym.response.frame):set_generated()
	end
	if sym.request then
		t:add(f.request_in, sym.request.frame):set_generated()
		if sym.rtt then t:add(f.response_time, ns_time(sym.rtt)):set_generated() end
	end
	if sym.stale then
		t:add_proto_expert_info(ex.stale, string.format(
			"Stale reply: TNS 0x%04X was answered in frame %d and newer commands followed",
			v.m.tns, sym.request.response.frame))
	end
	if sym.unmatched then
		t:add_proto_expert_info(ex.unmatched, string.format(
			"Reply with TNS 0x%04X to no command seen (stale, or its command was not captured)", v.m.tns))
	end
end

local function add_symbol(tree, tvb, sym)
	local wt, woff
	if #sym.pieces == 1 then
		wt, woff = tvb, sym.pieces[1].pos
	else
		wt, woff = ByteArray.new(sym.wire, true):tvb("Reassembled DF1"), 0
	end
	local wire = wt(woff, #sym.wire)
	local t = tree:add(df1, wire, "DF1 " .. summary(sym))
	t:add(f.symbol, wire, sym.kind):set_generated()
	t:add(f.dir, wire, sym.dir):set_generated()
	t:add(f.bytes, wire)
	if #sym.pieces > 1 then
		local pt = t:add(df1, wire, string.format("[%d records: %d bytes reassembled]", #sym.pieces, #sym.wire))
		for _, p in ipairs(sym.pieces) do
			pt:add(f.fragment, p.frame):append_text(string.format(" (%d bytes)", p.len)):set_generated()
		end
	end
	if sym.embedded then t:add(f.embedded, wire, true):set_generated() end
	local k = sym.kind
	if radio_mode() and (k == "NAK" or k == "ENQ" or k == "ACK" or k == "EOT") then
		-- a radio modem sends no link symbols: a node ignores this one
		t:add(df1, wire, "[radio modem: a stray link symbol, ignored]")
	elseif k == "NAK" then
		t:add_proto_expert_info(ex.nak, "NAK: the last frame was not received successfully (bad check, " ..
			"or no room); half duplex: the master's link reset")
	elseif k == "ENQ" and sym.enq_no then
		t:add(f.enq_retry, wire, sym.enq_no):set_generated()
		if sym.enq_for then t:add(f.enq_for, sym.enq_for.frame):set_generated() end
		t:add_proto_expert_info(ex.enq, string.format(
			"ENQ retry #%d: no response seen in time, the receiver is asked to repeat it", sym.enq_no))
	elseif k == "POLL" or (k == "ERROR" and sym.error == ID_ERR_BAD_BCC) then
		t:add(f.stn, wt(woff + 2, #sym.wire - 3), sym.station)
	end
	if k == "ERROR" then
		t:add(f.error_id, wire, sym.error):set_generated()
		t:add(f.error, wire, string.format("[%d] %s: %s", sym.error, ID_NAMES[sym.error] or "",
			error_text(sym))):set_generated()
		t:add_proto_expert_info(sym.cut and ex.incomplete or ex.malformed, error_text(sym))
	end
	if sym.check then
		local n = (sym.check == "CRC" and k ~= "POLL" and sym.error ~= ID_ERR_BAD_BCC) and 2 or 1
		local cr = wt(woff + #sym.wire - n, n)
		t:add(f.check, cr, sym.check):set_generated()
		t:add(f.check_ok, cr, sym.check_ok):set_generated()
		if n == 2 then t:add_le(f.crc, cr) else t:add(f.bcc, cr) end
		if not sym.check_ok then
			t:add(f.check_expected, cr, sym.expected):set_generated()
			t:add_proto_expert_info(ex.bad_check, check_text(sym))
		end
	end
	if sym.master and sym.has_station then
		t:add(f.master, wire, true):set_generated()
		t:add(f.stn, wt(woff + 2, 1), sym.station)
	end
	if k == "FRAME" or (k == "ERROR" and sym.data and #sym.data > 0) then
		local hdr = 2
		if sym.master then hdr = 2 + (sym.station == DLE and 2 or 1) + 2 end
		local body = sym.wire:sub(hdr + 1, hdr + #sym.data)
		local at, base
		if #sym.pieces == 1 and body == sym.data then
			at, base = wt, woff + hdr
		else
			at, base = ByteArray.new(sym.data, true):tvb("DF1 data (DLE unstuffed)"), 0
		end
		if k == "FRAME" then
			add_frame_fields(t, sym, at, base)
			add_tracking(t, sym)
		else
			t:add(f.data, at(base, #sym.data))
		end
	end
	return t
end

-- ---------------------------------------------------------------- dissection

local f_rtac_event = Field.new("rtacser.eventtype")
local f_tcp_stream = Field.new("tcp.stream")
local f_tcp_retrans = Field.new("tcp.analysis.retransmission")
local rtacser = Dissector.get("rtacser")

-- RTAC serial event types: 01/03 transmit start/end, 02/04 receive (tools/df1mon/mon_read.c).
local function rtac_dir(ev) return (ev == 0x01 or ev == 0x03) and "tx" or "rx" end

function df1.init()
	state_reset()
end

function df1.dissector(tvb, pinfo, tree)
	local base, dir, conv = 0, "rx", "rtac"
	local tcp = f_tcp_stream()
	if tcp then
		conv = "tcp" .. tostring(tcp.value)
		dir = pinfo.src_port == pinfo.match_uint and "rx" or "tx"
		if f_tcp_retrans() then
			-- the bytes were fed with the first copy of the segment
			pinfo.cols.protocol = "DF1"
			tree:add(df1, tvb(), "DF1 [TCP retransmission: bytes already seen]")
			pinfo.cols.info = "[TCP retransmission]"
			return tvb:len()
		end
	else
		if tvb:offset() > 0 then
			-- Decode As on RTAC serial's payload: the header is its dissector's
			local ev = f_rtac_event()
			dir = ev and rtac_dir(ev.value) or "rx"
		else
			-- the link type's own dissector: the RTAC header first, by Wireshark's dissector
			if tvb:len() < RTAC_HDR then return 0 end
			rtacser:call(tvb(0, RTAC_HDR):tvb(), pinfo, tree)
			dir = rtac_dir(tvb(8, 1):uint())
			base = RTAC_HDR
		end
	end
	pinfo.cols.protocol = "DF1"
	local n = pinfo.number
	local rec = get_rec(n)
	if not rec.fed then
		-- first sight of the record. Normally the first pass; a record first seen
		-- later (a caller that skips the first pass, as RTAC serial's Decode As does
		-- in tshark -2) is fed then, in order, and the capture's end is not judged.
		if pinfo.visited then G.late = true end
		rec.fed = true
		local st = get_stream(conv .. "/" .. dir, conv, dir)
		G.now = pinfo.rel_ts     -- small numbers: differences exact to the nanosecond
		for i = base, tvb:len() - 1 do feed(st, tvb(i, 1):uint(), n, i) end
		rec.pending = st.dec:busy()
		local ds = st.dec.state
		rec.pending_enq = ds == ST.APOLL_STN or ds == ST.APOLL_STN_DLE or ds == ST.APOLL_BCC
	elseif pinfo.visited and not G.finished and not G.late then
		G.finished = true
		for _, st in ipairs(G.streams) do finish(st) end
	end

	local info = {}
	table.sort(rec.syms, function(a, b) return a.id < b.id end)
	for _, sym in ipairs(rec.syms) do
		add_symbol(tree, tvb, sym)
		info[#info + 1] = summary(sym)
	end
	for _, p in ipairs(rec.parts) do
		local t = tree:add(df1, tvb(p.pos, p.len),
			string.format("DF1 [%d bytes of a %s completed in frame %d]", p.len, p.sym.kind, p.sym.frame))
		t:add(f.reassembled_in, p.sym.frame):set_generated()
		info[#info + 1] = string.format("[part of a %s completed in frame %d]", p.sym.kind, p.sym.frame)
	end
	if rec.pending and not G.finished and #rec.parts == 0 then
		-- tshark without -2: what the following records will decide
		local what = rec.pending_enq and "DLE ENQ: an ENQ, or a poll if STN and its BCC follow"
			or "a symbol continues in a later record"
		tree:add(df1, tvb(base, tvb:len() - base), "DF1 [" .. what .. "]")
		info[#info + 1] = "[" .. what .. "]"
	end
	if #info == 0 then
		if tvb:len() > base then
			tree:add(df1, tvb(base, tvb:len() - base), "DF1 [bytes outside any DF1 symbol]")
			info[#info + 1] = "[noise]"
		end
	end
	pinfo.cols.info = table.concat(info, "; ")
	return tvb:len()
end

-- ---------------------------------------------------------------- registration

local wtap = DissectorTable.get("wtap_encap")
local tcp_table = DissectorTable.get("tcp.port")
local tcp_port = 0

local function register()
	if df1.prefs.rtac then wtap:add(WTAP_RTAC_SERIAL, df1) else wtap:add(WTAP_RTAC_SERIAL, rtacser) end
	if tcp_port ~= df1.prefs.tcp_port then
		if tcp_port ~= 0 then tcp_table:remove(tcp_port, df1) end
		tcp_port = df1.prefs.tcp_port
		if tcp_port ~= 0 then tcp_table:add(tcp_port, df1) end
	end
end

function df1.prefs_changed()
	register()
end

register()
DissectorTable.get("rtacser.data"):add_for_decode_as(df1)
tcp_table:add_for_decode_as(df1)
