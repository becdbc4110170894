"""The shape of pnb-sweep's experiment files (docs/SWEEP.md, "Validation"): one JSON Schema per
kind, checked with jsonschema (Debian's python3-jsonschema) over the parsed TOML or JSON before
anything else reads the file, so that a malformed file ends in one error naming the file, the key
and what was expected, not in a traceback or a run that never ends. What a schema cannot say
stays with the loaders: scenes and paths that exist, placeholders that name an axis, converter
axes on a container (load_sweep, load_command_experiment).

Each schema's "description" is what the message says was expected; an enum lists its values and
an unknown key the known ones.
"""
import math
import re

import jsonschema

from sweep_command import BUILTIN, SweepError

# The metrics a play sweep may ask for (pnb_sweep.METRIC_FLAGS has their pnb-play options; frame:
# the whole frame against its path-traced truth, pnb-judge --frame-metrics).
METRICS = ("shadow", "gi", "sky", "lod", "frame")


def _finite_number(checker, instance):
    # TOML and JSON both spell nan and inf, and Python's parsers read them: no frame count,
    # interval or setting value is one. JSON integers are unbounded (no float holds 10**400).
    if isinstance(instance, bool):
        return False
    return isinstance(instance, int) or isinstance(instance, float) and math.isfinite(instance)


Validator = jsonschema.validators.extend(
    jsonschema.Draft202012Validator,
    type_checker=jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("number", _finite_number))

KIND = {"enum": ["play", "command"], "description": "a kind of experiment"}
TEXT = {"type": "string", "description": "a string"}
# Names become file and directory names (out/sweep/<name>/, the report's images).
NAME = {"type": "string", "pattern": "^[A-Za-z0-9][A-Za-z0-9._-]*$",
        "description": "a name of letters, digits, '.', '_' and '-'"}
VALUE = {"type": ["string", "number", "boolean"], "description": "a string, a finite number or a boolean"}
VALUES = {"type": "array", "minItems": 1, "items": VALUE,
          "description": "a non-empty list of strings, finite numbers or booleans"}
# pnb-play's settings are "section.name" (pnb-play --list-settings), pnb-convert's options
# "convert.OPTION". A TOML key left unquoted is a nested table: "shadows" holding "technique".
SETTING = {"type": "string", "pattern": r"^[a-z][a-z0-9_]*\.[a-z0-9][a-z0-9_-]*$",
           "description": "a setting key \"section.name\" or \"convert.OPTION\", quoted in TOML "
                          "(\"shadows.technique\" = ...)"}
PLACEHOLDER = {"type": "string", "pattern": "^[A-Za-z_][A-Za-z0-9_]*$", "not": {"enum": list(BUILTIN)},
               "description": "a placeholder name (letters, digits, '_'; not %s)" % ", ".join(BUILTIN)}


def _axes(keys, what):
    """`axes`: one table of keys to lists of values, or a non-empty list of such tables (their union)."""
    table = {"propertyNames": keys, "additionalProperties": VALUES}
    described = "a table of %s to non-empty lists of values" % what
    either = "%s ([axes]), or a non-empty list of such tables ([[axes]])" % described
    return {"type": ["object", "array"], "description": either,
            "if": {"type": "array"},
            "then": {"minItems": 1, "description": either,
                     "items": dict(table, type="object", description=described)},
            "else": table}


PLAY = {
    "type": "object",
    "required": ["scenes"],
    "additionalProperties": False,
    "properties": {
        "name": NAME,
        "kind": KIND,
        "description": TEXT,
        "frames": {"type": "integer", "minimum": 1, "description": "a whole number of frames >= 1"},
        "size": {"type": "string", "pattern": "^[1-9][0-9]*x[1-9][0-9]*$",
                 "description": "WIDTHxHEIGHT in pixels, like \"320x180\""},
        "metrics": {"type": "object", "additionalProperties": False,
                    "description": "a table of metrics to frame intervals, like { shadow = 8 }",
                    "properties": {m: {"type": "integer", "minimum": 1,
                                       "description": "a frame interval, a whole number >= 1"} for m in METRICS}},
        "fixed": {"type": "object", "propertyNames": SETTING, "additionalProperties": VALUE,
                  "description": "a table of setting keys to values"},
        "axes": _axes(SETTING, "setting keys"),
        "scenes": {
            "type": "array", "minItems": 1,
            "description": "a non-empty list of tables ([[scenes]]), each with a source",
            "items": {
                "type": "object", "required": ["source"], "additionalProperties": False,
                "description": "a table ([[scenes]]) with a source",
                "properties": {
                    "name": NAME,
                    "source": {"type": "string", "minLength": 1,
                               "description": "a non-empty string: the scene's file, relative to the sweep file"},
                    "convert": {"type": "array", "items": TEXT,
                                "description": "a list of strings: pnb-convert options"},
                    "path": {"type": "string", "minLength": 1,
                             "description": "a non-empty string: a camera path's file, relative to the sweep file"},
                }}},
    },
}

STRINGS = {"type": "array", "minItems": 1, "items": TEXT, "description": "a non-empty list of strings"}

COMMAND = {
    "type": "object",
    "required": ["command"],
    "additionalProperties": False,
    "properties": {
        "name": NAME,
        "kind": KIND,
        "description": TEXT,
        "command": dict(STRINGS, description="a non-empty list of strings: the program and its arguments"),
        "args": {"type": "array", "items": TEXT, "description": "a list of strings: default extra arguments"},
        "depends": dict(STRINGS, description="a non-empty list of strings: the files the job's results depend on"),
        "env": {"type": "object", "additionalProperties": TEXT,
                "propertyNames": {"type": "string", "pattern": "^[A-Za-z_][A-Za-z0-9_]*$",
                                  "description": "an environment variable's name"},
                "description": "a table of environment variables to strings"},
        "figures": {
            "type": "object", "required": ["file"], "additionalProperties": False,
            "description": "a table with 'file' and either 'keys' (JSON) or 'label' and 'columns' (CSV, or "
                           "JSON records with 'rows')",
            "properties": {
                "file": {"type": "string", "minLength": 1,
                         "description": "a non-empty string: a glob in the job's directory"},
                "keys": dict(STRINGS, description="a non-empty list of strings: dotted paths in the JSON"),
                "rows": {"type": "string", "minLength": 1,
                         "description": "a non-empty string: the dotted path of a list of records in the JSON"},
                "label": dict(STRINGS, description="a non-empty list of strings: the columns naming a row"),
                "columns": dict(STRINGS, description="a non-empty list of strings: the columns holding figures"),
            },
            # A CSV file, or JSON records: label and columns; any other JSON: keys.
            "if": {"anyOf": [{"required": ["rows"]},
                             {"required": ["file"], "properties": {"file": {"pattern": r"\.csv$"}}}]},
            "then": {"required": ["label", "columns"]},
            "else": {"required": ["keys"]}},
        "axes": _axes(PLACEHOLDER, "placeholder names"),
    },
}

# Checked first: the kind chooses the schema (and a file that is not a table has no kind).
TOP = {"type": "object", "properties": {"kind": KIND}, "description": "a table, a JSON object"}

SCHEMAS = {"play": PLAY, "command": COMMAND}

_BARE_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_-]*$")


def key_path(parts):
    """A key's place in the file as one would write it: scenes[1].source, axes[0]."shadows.technique"."""
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += "[%d]" % p
        else:
            name = p if _BARE_KEY.match(p) else '"%s"' % p.replace('"', '\\"')
            out += name if not out else "." + name
    return out


def _shown(value):
    """A value as the message shows what was found."""
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "a list" if value else "an empty list"
    if isinstance(value, bool):
        return "true" if value else "false"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _declared(root, schema_path, name):
    """The schema of property `name` nearest to where a `required` failed (it may sit in a
    then/else beside the properties, or be the object's own)."""
    node, nodes = root, [root]
    for part in list(schema_path)[:-1]:
        node = node[part]
        nodes.append(node)
    declared = [n["properties"][name] for n in nodes if isinstance(n, dict) and name in (n.get("properties") or {})]
    return declared[-1] if declared else None


def _message(root, error):
    where = list(error.path)
    here = key_path(where)
    if "propertyNames" in error.relative_schema_path:
        return "key '%s' must be %s" % (key_path(where + [error.instance]), error.schema["description"])
    if error.validator == "additionalProperties":
        known = sorted(error.schema.get("properties", {}))
        extra = sorted(set(error.instance) - set(known))[0]
        return "unknown key '%s' (known: %s)" % (key_path(where + [extra]), ", ".join(known))
    if error.validator == "required":
        name = next(n for n in error.validator_value if n not in error.instance)
        declared = _declared(root, error.relative_schema_path, name)
        return "needs '%s'%s" % (key_path(where + [name]), " (%s)" % declared["description"] if declared else "")
    if error.validator == "enum":
        return "%s: %s is not %s (%s)" % (here, _shown(error.instance), error.schema["description"],
                                          ", ".join(error.validator_value))
    if "description" in error.schema:
        return "'%s' must be %s (got %s)" % (here, error.schema["description"], _shown(error.instance)) if here \
            else "the top level must be %s (got %s)" % (error.schema["description"], _shown(error.instance))
    return "%s: %s" % (here or "the top level", error.message)


def _check(path, schema, data):
    error = jsonschema.exceptions.best_match(Validator(schema).iter_errors(data))
    if error is not None:
        raise SweepError("%s: %s" % (path, _message(schema, error)))


def validate(path, data):
    """SweepError naming `path`, the key and what was expected when `data` (the parsed file) is not
    an experiment file of its kind: the most telling error (jsonschema's best_match), one per message."""
    _check(path, TOP, data)
    _check(path, SCHEMAS[data.get("kind", "play")], data)
