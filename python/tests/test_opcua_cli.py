# SPDX-License-Identifier: MPL-2.0
"""df1opcua's parts that need no asyncua: the users file (a salted scrypt hash, checked here
against hashlib directly), --listen, the exit status of usage errors. The server itself is
tested through an independent OPC UA client by tests/integration/it_df1opcua.sh."""
import hashlib
import os
import stat

import pytest

from libdf1.opcua import cli, users


def test_add_user_stores_a_salted_scrypt_hash(tmp_path):
    path = str(tmp_path / "users")
    assert users.add_user(path, "alice", "s3cret pw") is True
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o600
    text = open(path).read()
    assert "s3cret" not in text
    name, _, rest = text.strip().partition(":")
    kind, n, r, p, salt, digest = rest.split("$")
    assert (name, kind) == ("alice", "scrypt")
    assert len(bytes.fromhex(salt)) == 16
    want = hashlib.scrypt(b"s3cret pw", salt=bytes.fromhex(salt), n=int(n), r=int(r), p=int(p),
                          maxmem=64 * 1024 * 1024, dklen=32)
    assert bytes.fromhex(digest) == want


def test_verify_and_replace(tmp_path):
    path = str(tmp_path / "users")
    users.add_user(path, "alice", "one")
    users.add_user(path, "bob", "two")
    first = users.load(path)["alice"]
    assert users.add_user(path, "alice", "three") is False      # replaced, not added
    table = users.load(path)
    assert sorted(table) == ["alice", "bob"]
    assert table["alice"] != first
    assert users.verify(table["alice"], "three")
    assert not users.verify(table["alice"], "one")
    assert users.verify(table["bob"], "two")
    assert not users.verify(table.get("carol"), "two")
    assert not users.verify(table["bob"], None)


def test_same_password_different_salt(tmp_path):
    assert users.make_entry("a", "pw").split("$")[4] != users.make_entry("a", "pw").split("$")[4]


@pytest.mark.parametrize("name", ["", "a b", "a:b", "#x", "x" * 65])
def test_bad_user_names(tmp_path, name):
    with pytest.raises(users.UsersError):
        users.add_user(str(tmp_path / "users"), name, "pw")


def test_malformed_users_file_names_its_line(tmp_path):
    path = tmp_path / "users"
    path.write_text("# users\nalice:plain-password\n")
    with pytest.raises(users.UsersError, match=r"users:2:"):
        users.load(str(path))


@pytest.mark.parametrize("text,want", [
    ("4840", ("127.0.0.1", 4840)),
    ("0.0.0.0:4841", ("0.0.0.0", 4841)),
    ("[::1]:4842", ("::1", 4842)),
    ("plc-host:4843", ("plc-host", 4843)),
])
def test_listen(text, want):
    assert cli.parse_listen(text) == want


@pytest.mark.parametrize("text", ["", "0", "65536", "1.2.3.4:", "::1:4840", "a:b"])
def test_listen_refused(text):
    with pytest.raises(cli.Usage):
        cli.parse_listen(text)


def test_loopback():
    assert cli.is_loopback("127.0.0.1") and cli.is_loopback("127.0.0.2") and cli.is_loopback("::1")
    assert not cli.is_loopback("0.0.0.0") and not cli.is_loopback("192.0.2.1")


def test_line_name():
    assert cli.line_name("/dev/ttyUSB0") == "ttyUSB0"
    assert cli.line_name("tcp://10.0.0.5:2101") == "10_0_0_5_2101"


def test_usage_errors_exit_2(capsys, tmp_path):
    assert cli.main(["--bogus"]) == 2
    assert cli.main(["-d", "/dev/null"]) == 2
    assert "--map FILE.csv is required" in capsys.readouterr().err
    assert cli.main(["-d", "/dev/null", "--map", str(tmp_path / "none.csv")]) == 2
    assert cli.main(["--add-user", "alice"]) == 2
    assert cli.main(["-b", "nine"]) == 2


def test_write_timeout_option():
    p = cli.build_parser()
    assert p.parse_args([]).write_timeout == 30000          # df1gw's default
    assert p.parse_args(["--write-timeout", "1"]).write_timeout == 1
    assert p.parse_args(["--write-timeout", "3600000"]).write_timeout == 3600000
    assert p.parse_args(["--write-timeout", "0x12C"]).write_timeout == 300


@pytest.mark.parametrize("value", ["0", "3600001", "-5", "fast", ""])
def test_write_timeout_refused(capsys, tmp_path, value):
    m = tmp_path / "map.csv"
    m.write_text("Tag,Command,Type,Station,PLC_Type,Address\nX,Read,INT,1,SLC,N7:0\n")
    assert cli.main(["-d", "/dev/null", "--map", str(m), "--write-timeout", value]) == 2
    assert "--write-timeout" in capsys.readouterr().err
