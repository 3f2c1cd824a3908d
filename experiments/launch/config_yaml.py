"""A config's YAML read as untrusted text, each refusal a :class:`ConfigError` in one line.

:func:`read_yaml` reads a config file's text or a ``--set`` value: its events are scanned
first, without recursing, so that an alias (a few nested ones expand to gigabytes) or nesting
past :data:`MAX_DEPTH` is refused before anything recursive reads it; then YAML's safe loader
(libyaml's where PyYAML has it) reads it, refusing a key given twice in one mapping and an
integer too long to be a value, each named by its field path.
"""

from __future__ import annotations

from typing import Any

import yaml

# How deep a config's YAML may nest (a config needs a handful of levels): its reader and its
# checks recurse, and a file of thousands of nested ``[`` would exhaust the stack.
MAX_DEPTH = 64
# The characters an integer of a config may be written in (2**64 takes 20 digits): a longer
# one is refused before Python converts it, which takes time growing with its square.
MAX_INT_CHARS = 100


class ConfigError(ValueError):
    """A config problem: ``file: field.path: what is wrong``."""

    def __init__(self, source: str, path: str, message: str) -> None:
        self.source, self.path, self.message = source, path, message
        super().__init__(f"{source}: {path}: {message}" if path else f"{source}: {message}")


class _Refused(yaml.constructor.ConstructorError):
    """What :class:`_ConfigLoader` refuses: ``problem`` at the node of ``node_mark`` (the
    field it names is found from that mark)."""

    def __init__(self, problem: str, node_mark: yaml.Mark) -> None:
        super().__init__(None, None, problem, node_mark)
        self.node_mark = node_mark


# YAML's safe loader on libyaml's parser where PyYAML has it (far faster on a config near its
# size bound), else on the pure-Python one.
_SAFE_LOADER: type = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class _ConfigLoader(_SAFE_LOADER):
    """YAML's safe loader that refuses a key given twice in one mapping (the safe loader keeps
    the last, silently) and an integer too long to be a value (:data:`MAX_INT_CHARS`)."""

    def construct_mapping(self, node: yaml.Node, deep: bool = False) -> dict:
        seen: dict[Any, yaml.Node] = {}
        for key_node, _ in node.value if isinstance(node, yaml.MappingNode) else ():
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = self.construct_object(key_node, deep=True)
            try:
                first = seen.setdefault(key, key_node)
            except TypeError:  # an unhashable key: the safe loader's own error
                continue
            if first is not key_node:
                lines = sorted({first.start_mark.line + 1, key_node.start_mark.line + 1})
                raise _Refused(f"duplicate key {key!r} (line{'s' * (len(lines) > 1)} "
                               f"{' and '.join(map(str, lines))})", key_node.start_mark)
        return super().construct_mapping(node, deep)

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        text = self.construct_scalar(node)
        if len(text) > MAX_INT_CHARS:
            raise _Refused(f"an integer written in {len(text):,} characters, more than the "
                           f"{MAX_INT_CHARS} a config's integers may take", node.start_mark)
        return super().construct_yaml_int(node)


_ConfigLoader.add_constructor("tag:yaml.org,2002:int", _ConfigLoader.construct_yaml_int)


def _problem(error: yaml.YAMLError) -> str:
    """A YAML error in one line: what is wrong and where (line and column)."""
    if not isinstance(error, yaml.MarkedYAMLError):
        return " ".join(str(error).split())
    mark = error.problem_mark or error.context_mark
    where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark else ""
    return " ".join(f"{error.problem or error.context}{where}".split())


def _check_events(text: str, source: str, field: str) -> None:
    """Scan ``text``'s YAML events, which the parser yields without recursing: ConfigError on
    an alias (a few nested ones expand to gigabytes) or on nesting deeper than
    :data:`MAX_DEPTH`, which stops the scan there, before anything recursive reads it."""
    depth = 0
    try:
        for event in yaml.parse(text, Loader=_ConfigLoader):
            if isinstance(event, yaml.AliasEvent):
                raise ConfigError(source, field, "YAML aliases (*name) are not accepted: a few "
                                  "nested ones expand to gigabytes; write the values out")
            depth += isinstance(event, yaml.CollectionStartEvent)
            depth -= isinstance(event, yaml.CollectionEndEvent)
            if depth > MAX_DEPTH:
                raise _too_deep(source, field, event.start_mark)
    except yaml.MarkedYAMLError as error:  # libyaml's own bound, met while it reads ahead
        if "nesting depth" not in str(error.problem) or error.problem_mark is None:
            raise
        raise _too_deep(source, field, error.problem_mark) from None


def _too_deep(source: str, field: str, mark: yaml.Mark) -> ConfigError:
    """The refusal of a config nested deeper than :data:`MAX_DEPTH`, at ``mark``."""
    return ConfigError(source, field, f"nested deeper than {MAX_DEPTH} levels (line "
                       f"{mark.line + 1}); a config needs a few")


def _field_at(node: yaml.Node, index: int, path: tuple[str, ...] = ()) -> tuple[str, ...]:
    """The field path, from ``node``, of the key or value that starts at character ``index``
    (``()`` where none does): the deepest node holding it names it."""
    children: list[tuple[str, yaml.Node, yaml.Node | None]] = []
    if isinstance(node, yaml.MappingNode):
        children = [(str(k.value), k, v) for k, v in node.value]
    elif isinstance(node, yaml.SequenceNode):
        children = [(str(i), v, None) for i, v in enumerate(node.value)]
    for name, *nodes in children:
        for child in nodes:
            if child is not None and child.start_mark.index <= index < child.end_mark.index:
                return _field_at(child, index, (*path, name)) or (*path, name)
    return ()


def read_yaml(text: str, source: str, field: str = "") -> Any:
    """The data of the YAML ``text`` (a config file's, or a ``--set`` value for ``field``),
    read safely: no aliases, nesting, duplicate keys or huge integers (:func:`_check_events`,
    :class:`_ConfigLoader`); else ConfigError naming ``source`` and the field, in one line."""
    try:
        _check_events(text, source, field)
        return yaml.load(text, Loader=_ConfigLoader)
    except ConfigError:
        raise
    except _Refused as error:
        inner = _field_at(yaml.compose(text, Loader=_ConfigLoader), error.node_mark.index)
        path = ".".join(p for p in (field, *inner) if p)
        raise ConfigError(source, path, str(error.problem)) from None
    except (yaml.YAMLError, ValueError, TypeError, OverflowError) as error:
        # a constructor's own error (a date such as 2001-13-45, a !!float that is no number)
        # is not a YAMLError, and is said as it is
        problem = _problem(error) if isinstance(error, yaml.YAMLError) else " ".join(
            str(error).split())
        if field:
            shown = text if len(text) <= 40 else f"{text[:40]}..."
            raise ConfigError(source, field, f"cannot read value {shown!r}: {problem}") from None
        raise ConfigError(source, "", f"not valid YAML: {problem}") from None
