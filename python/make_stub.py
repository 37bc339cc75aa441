# SPDX-License-Identifier: MIT
"""Writes dualgraph.pyi from the built module's pybind11 signatures and docstrings (run at build time).

Usage: python make_stub.py OUTPUT.pyi  (with the built module on PYTHONPATH). No dependency beyond the
standard library: every name the module has gets a stub entry, typed as pybind11's signature line says.
"""
import inspect
import re
import sys

import dualgraph

TYPING = ("List", "Dict", "Optional", "Tuple", "Callable", "Union", "Set", "Iterator", "Any")
SIGNATURE = re.compile(r"^(?:\d+\. )?(\w*)\((.*)\)(?: -> (.+))?$")


def annotation(text):
    """pybind11's type text -> a stub annotation (typing. and numpy.typing. qualified, dualgraph. dropped)."""
    text = text.replace("dualgraph.", "")
    text = re.sub(r"numpy\.ndarray\[([\w.]+)\]", r"numpy.typing.NDArray[\1]", text)
    text = re.sub(r"(?<![\w.])(%s)\b" % "|".join(TYPING), r"typing.\1", text)
    return text


def split_arguments(text):
    """Splits `a: T, b: U[V, W] = x` at the commas outside brackets and quotes."""
    parts, depth, quote, current = [], 0, None, ""
    for char in text:
        if quote:
            quote = None if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in "[(<{":
            depth += 1
        elif char in "])>}":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(current.strip())
            current = ""
            continue
        current += char
    if current.strip():
        parts.append(current.strip())
    return parts


def parameters(text, method):
    out = []
    for k, part in enumerate(split_arguments(text)):
        if part.startswith("*"):
            out.append(part)
            continue
        name, _, rest = part.partition(":")
        type_text, has_default, _ = rest.partition("=")
        if method and k == 0:
            out.append(name.strip())
        else:
            out.append(name.strip() + ": " + annotation(type_text.strip()) + (" = ..." if has_default else ""))
    return ", ".join(out)


def signatures(doc):
    """[(name, arguments, return)] of a pybind11 docstring (one per overload) and the remaining description."""
    lines = (doc or "").splitlines()
    found, description = [], []
    for line in lines:
        match = SIGNATURE.match(line.strip())
        if match and (not found or line.strip()[0].isdigit()):
            found.append(match.groups())
        elif line.strip() != "Overloaded function.":
            description.append(line)
    if len(found) > 1 and found[0][1] == "*args, **kwargs":
        found = found[1:]
    return found, "\n".join(description).strip()


def docstring(text, indent):
    if not text:
        return ""
    text = text.replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    body = "\n".join((indent + line) if line.strip() else "" for line in text.splitlines())
    return f'{indent}"""\n{body}\n{indent}"""\n'


def function(obj, name, indent, method, decorator=None):
    found, description = signatures(obj.__doc__)
    if not found:
        raise SystemExit(f"make_stub.py: no pybind11 signature for {name}: {obj.__doc__!r}")
    out = ""
    for _, arguments, returns in found:
        if len(found) > 1:
            out += f"{indent}@typing.overload\n"
        if decorator:
            out += f"{indent}@{decorator}\n"
        out += f"{indent}def {name}({parameters(arguments, method)}) -> {annotation(returns or 'None')}:\n"
        out += docstring(description, indent + "    ") or ""
        out += f"{indent}    ...\n"
    return out


def klass(cls):
    if issubclass(cls, BaseException):
        bases = ", ".join(b.__name__ if b.__module__ == "dualgraph" else b.__name__ for b in cls.__bases__)
        return f"class {cls.__name__}({bases}):\n" + docstring(cls.__doc__, "    ") + "    code: str\n"
    out = f"class {cls.__name__}:\n" + docstring(cls.__doc__, "    ")
    for name, member in sorted(cls.__dict__.items()):
        if name.startswith("_") and name not in ("__init__", "__repr__"):
            continue
        if name == "__init__" and not (member.__doc__ or "").startswith("__init__("):
            continue  # no constructor bound: pybind11's placeholder, which raises
        if isinstance(member, property):
            found, description = signatures(member.fget.__doc__)
            returns = annotation(found[0][2]) if found else "typing.Any"
            doc = member.__doc__ if member.__doc__ and member.__doc__ != member.fget.__doc__ else description
            out += f"    @property\n    def {name}(self) -> {returns}:\n" + docstring(doc, "        ") + "        ...\n"
            if member.fset is not None:
                setter, _ = signatures(member.fset.__doc__)
                value = "value: " + parameters(setter[0][1], True).split(", ", 1)[1].split(": ", 1)[1] if setter else "value"
                out += f"    @{name}.setter\n    def {name}(self, {value}) -> None: ...\n"
        elif isinstance(member, staticmethod):
            out += function(member.__func__, name, "    ", False, "staticmethod")
        elif callable(member):
            out += function(member, name, "    ", True)
    return out


def main(path):
    header = ("# Generated by python/make_stub.py from the module's signatures: do not edit.\n"
              "import os\nimport typing\n\nimport numpy\nimport numpy.typing\n\n__version__: str\n\n")
    names = sorted(n for n in dir(dualgraph) if not n.startswith("_"))
    classes = [getattr(dualgraph, n) for n in names if inspect.isclass(getattr(dualgraph, n))]
    # Exceptions first, base classes before subclasses; then the other classes, then the functions.
    classes.sort(key=lambda c: (not issubclass(c, BaseException), len(c.__mro__), c.__name__))
    body = "".join(klass(c) + "\n" for c in classes)
    for name in names:
        obj = getattr(dualgraph, name)
        if not inspect.isclass(obj):
            body += function(obj, name, "", False) + "\n"
    with open(path, "w") as out:
        out.write(f'"""{dualgraph.__doc__}"""\n' + header + body.rstrip("\n") + "\n")


if __name__ == "__main__":
    main(sys.argv[1])
