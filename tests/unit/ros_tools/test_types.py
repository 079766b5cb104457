"""Type names as users write them, and field type strings as messages describe themselves."""

from __future__ import annotations

import pytest

from ros_tools.types import (
    FieldType,
    import_type,
    looks_like_type_name,
    parse_field_type,
    parse_type_name,
    type_name_of,
)


@pytest.mark.parametrize(
    ("text", "kind", "expected"),
    [
        ("geometry_msgs/msg/Twist", "msg", "geometry_msgs/msg/Twist"),
        ("geometry_msgs/Twist", "msg", "geometry_msgs/msg/Twist"),
        ("std_srvs/SetBool", "srv", "std_srvs/srv/SetBool"),
        (" nav2_msgs/action/Wait ", "action", "nav2_msgs/action/Wait"),
    ],
)
def test_parse_type_name_accepts_full_and_short_forms(text, kind, expected):
    assert str(parse_type_name(text, kind)) == expected


@pytest.mark.parametrize(
    ("text", "kind", "error"),
    [
        ("Twist", "msg", "is not a type name"),
        ("geometry_msgs/msg/Twist/extra", "msg", "is not a type name"),
        ("{data: 1}", "msg", "is not a type name"),
        ("std_srvs/srv/SetBool", "msg", "is a srv type, expected a msg type"),
        ("std_msgs/String", "idl", "interface kind must be one of"),
    ],
)
def test_parse_type_name_rejects_malformed_names(text, kind, error):
    with pytest.raises(ValueError, match=error):
        parse_type_name(text, kind)


def test_looks_like_type_name_tells_types_from_yaml():
    assert looks_like_type_name("std_srvs/srv/SetBool")
    assert looks_like_type_name("std_srvs/SetBool")
    assert not looks_like_type_name("{data: true}")
    assert not looks_like_type_name("data: 'a/b'")


def test_import_type_returns_the_generated_classes():
    from std_msgs.msg import String
    from std_srvs.srv import SetBool

    assert import_type("std_msgs/String") is String
    assert import_type("std_srvs/srv/SetBool", "srv") is SetBool
    assert type_name_of(String) == "std_msgs/msg/String"
    assert type_name_of(SetBool.Request()) == "std_srvs/srv/SetBool_Request"


@pytest.mark.parametrize(
    ("text", "error"),
    [
        ("no_such_pkg_xyz/msg/Thing", "unknown msg type 'no_such_pkg_xyz/msg/Thing': cannot import"),
        ("std_msgs/msg/NoSuchType", "std_msgs.msg has no type 'NoSuchType'"),
    ],
)
def test_import_type_names_what_is_missing(text, error):
    with pytest.raises(ValueError, match=error):
        import_type(text)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("double", FieldType("double")),
        ("std_msgs/Header", FieldType("std_msgs/Header")),
        ("double[9]", FieldType("double", "array", 9)),
        ("sequence<uint8>", FieldType("uint8", "sequence", None)),
        ("sequence<double, 3>", FieldType("double", "sequence", 3)),
        ("sequence<rcl_interfaces/FloatingPointRange, 1>",
         FieldType("rcl_interfaces/FloatingPointRange", "sequence", 1)),
        ("string<255>", FieldType("string", string_bound=255)),
        ("sequence<string<10>, 5>", FieldType("string", "sequence", 5, 10)),
        ("string<4>[3]", FieldType("string", "array", 3, 4)),
    ],
)
def test_parse_field_type_reads_every_container_shape(text, expected):
    assert parse_field_type(text) == expected


def test_field_type_describes_itself_as_ros_users_write_it():
    assert parse_field_type("sequence<double, 3>").describe() == "sequence<double, 3>"
    assert parse_field_type("double[9]").describe() == "double[9]"
    assert parse_field_type("string<255>").describe() == "string<=255"
    assert parse_field_type("std_msgs/Header").is_message
    assert not parse_field_type("sequence<octet>").is_message


def test_parse_field_type_rejects_unknown_primitives():
    with pytest.raises(ValueError, match="unrecognised field type 'float128'"):
        parse_field_type("float128")
