#!/usr/bin/python3
"""Rewrites a Gmsh-style Abaqus/CalculiX deck (.inp) into the style of Abaqus/CAE decks, so that
the tests can read the same mesh through both forms of boundary groups.

Gmsh (-format inp) writes the faces of a physical surface as 2D elements (CPS3, CPS4, CPS6,
CPS8) and the group as an *ELSET of their labels. This tool drops those 2D elements and writes
every ELSET made only of them (or of sets of them) as an element-based surface instead:

    *SURFACE, NAME=<name>, TYPE=ELEMENT
    <3D element label>, S<k>          half of the faces (alternate ones), directly
    _<name>_S<k>, S<k>                the other half, through internal element sets
                                      *ELSET, ELSET=_<name>_S<k> written before the surface

where the 3D element is the one with the 2D element's corner nodes on its face number k
(Abaqus numbering). A 2D element that is no face of a 3D element is an error (exit status 1).
The 3D elements (C3D4, C3D10, C3D8, C3D20, C3D6, C3D15, any suffix), their ELSETs, every
*NSET and *NODE are kept; other elements (e.g. line elements) and keywords pass through. A
`**` comment heads the output and a material/step block that is no mesh data ends it.

    usage: inp_surfaces.py IN.inp OUT.inp [--upper] [--generate] [--split-lines]

    --upper        every keyword, parameter and set name in upper case
    --generate     *NSET, GENERATE for the node sets that are one arithmetic run; adds NSET
                   NALL (GENERATE, when the node labels are 1..N) and ELSET EALL of the 3D
                   elements (GENERATE when their labels are contiguous)
    --split-lines  at most 8 numbers on an element's line (continued after a trailing comma)
                   and 8 labels on a set's line (else 16 and 16, the Abaqus maxima)

The input may have keywords in any case with spaces around commas and `=`, `**` comments,
CRLF line ends, trailing commas, GENERATE sets and sets named among the members of sets.
"""
import re
import sys

# Faces of the volume elements by their Abaqus numbers S1, S2, ...: 0-based corner positions.
FACES = {
    "tet": [(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)],
    "hex": [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)],
    "wedge": [(0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)],
}
SOLID_SHAPE = {4: "tet", 10: "tet", 8: "hex", 20: "hex", 6: "wedge", 15: "wedge"}
SOLID_TYPE = re.compile(r"^C3D(4|10|8|20|6|15)[A-Z]*$")
FACE_TYPE = re.compile(r"^(?:CPS|CPE|CAX|S|M3D|R3D|SFM3D)(3|4|6|8)(?:[A-Z][A-Z0-9]*)?$"
                       r"|^STRI(3|65)$")

TRAILER = ["*MATERIAL, NAME=STEEL", "*ELASTIC", "2.1e11, 0.3", "*STEP", "*STATIC",
           "*END STEP"]


class InpError(Exception):
    """A deck this tool cannot rewrite; the message says why."""


def solid_nodes(etype):
    """The node count of a volume element type (C3D10M -> 10), or None for other types."""
    m = SOLID_TYPE.match(etype.upper())
    return int(m.group(1)) if m else None


def face_nodes(etype):
    """The node count of a face (2D) element type (CPS6 -> 6), or None for other types."""
    m = FACE_TYPE.match(etype.upper())
    if not m:
        return None
    if m.group(1):
        return int(m.group(1))
    return 3 if m.group(2) == "3" else 6


def parse_keyword(line):
    """Splits a keyword line into (KEYWORD, {PARAM: value}); keys upper case, values as written.

    Parameters without a value (GENERATE) map to None.
    """
    parts = [p.strip() for p in line[1:].split(",")]
    keyword = " ".join(parts[0].upper().split())
    params = {}
    for part in parts[1:]:
        if not part:
            continue
        if "=" in part:
            key, value = part.split("=", 1)
            params[" ".join(key.upper().split())] = value.strip()
        else:
            params[" ".join(part.upper().split())] = None
    return keyword, params


def read_blocks(path):
    """The deck as a list of blocks: dicts with the keyword line, keyword, params and data lines.

    Comment lines (`**`) and blank lines are dropped; lines before the first keyword too.
    """
    with open(path, newline="") as f:
        text = f.read()
    blocks = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("**"):
            continue
        if line.startswith("*"):
            keyword, params = parse_keyword(line)
            blocks.append({"line": line, "keyword": keyword, "params": params, "data": [],
                           "lineno": number})
        elif blocks:
            blocks[-1]["data"].append(line)
    return blocks


def tokens(line):
    """The comma-separated fields of a data line, without the empty one after a trailing comma."""
    fields = [t.strip() for t in line.split(",")]
    while fields and not fields[-1]:
        fields.pop()
    return fields


def read_elements(block):
    """The elements of an *ELEMENT block as a list of (label, [node labels]).

    An element continues on the next line while it has fewer nodes than its type needs (types
    this tool knows) or while its line ends with a comma (other types).
    """
    etype = block["params"].get("TYPE", "")
    count = solid_nodes(etype) or face_nodes(etype)
    elements, pending = [], []
    for line in block["data"]:
        pending += [int(t) for t in tokens(line)]
        if count is None:
            if line.rstrip().endswith(","):
                continue
        elif len(pending) < count + 1:
            continue
        elif len(pending) > count + 1:
            raise InpError(f"element {pending[0]} of type {etype} has {len(pending) - 1} "
                           f"nodes, not {count}")
        elements.append((pending[0], pending[1:]))
        pending = []
    if pending:
        raise InpError(f"element {pending[0]} of type {etype} is cut short")
    return elements


def read_members(block):
    """The members of an *NSET or *ELSET block: ints for labels, strings for set names."""
    fields = [t for line in block["data"] for t in tokens(line)]
    if "GENERATE" in block["params"]:
        members = []
        for i in range(0, len(fields), 3):
            first, last = int(fields[i]), int(fields[i + 1])
            step = int(fields[i + 2]) if i + 2 < len(fields) else 1
            members += range(first, last + 1, step)
        return members
    return [int(t) if t.lstrip("+-").isdigit() else t for t in fields]


def set_name(block, key):
    """The set a block defines (the value of its ELSET or NSET parameter), quotes removed."""
    return block["params"][key].strip('"')


def collect_elsets(blocks):
    """All element sets by upper-case name: lists of members (labels and set names) in order.

    Repeated definitions extend a set, as in Abaqus; an *ELEMENT block's ELSET parameter adds
    its elements to that set.
    """
    sets = {}
    for block in blocks:
        if block["keyword"] == "ELSET" and "ELSET" in block["params"]:
            sets.setdefault(set_name(block, "ELSET").upper(), []).extend(block["members"])
        elif block["keyword"] == "ELEMENT" and "ELSET" in block["params"]:
            labels = [label for label, _ in block["elements"]]
            sets.setdefault(set_name(block, "ELSET").upper(), []).extend(labels)
    return sets


def expand(name, sets, seen=()):
    """The element labels of a set, with the sets named among its members expanded."""
    if name in seen:
        raise InpError(f"set {name} contains itself")
    if name not in sets:
        raise InpError(f"set {name} is used but not defined")
    labels = []
    for member in sets[name]:
        if isinstance(member, int):
            labels.append(member)
        else:
            labels += expand(member.strip('"').upper(), sets, seen + (name,))
    return labels


def unique(labels):
    """The labels without repeats, in the order of their first appearance."""
    return list(dict.fromkeys(labels))


def find_faces(face_elements, solids):
    """Maps each face element label to (3D element label, Abaqus face number k) sharing corners.

    face_elements: {label: corner node labels}; solids: [(label, nodes)] of the volume elements.
    Only the faces whose sorted corners are wanted are stored, so large meshes stay cheap. A face
    shared by two volume elements goes to the first one in the file. Raises InpError naming the
    face elements that are no face of a volume element.
    """
    key_of = {label: tuple(sorted(corners)) for label, corners in face_elements.items()}
    wanted = set(key_of.values())
    found = {}
    for label, nodes in solids:
        for k, positions in enumerate(FACES[SOLID_SHAPE[len(nodes)]], start=1):
            key = tuple(sorted(nodes[p] for p in positions))
            if key in wanted and key not in found:
                found[key] = (label, k)
    missing = sorted(label for label, key in key_of.items() if key not in found)
    if missing:
        shown = ", ".join(str(m) for m in missing[:10])
        raise InpError(f"{len(missing)} face element(s) are no face of a 3D element: {shown}")
    return {label: found[key] for label, key in key_of.items()}


def chunks(items, size):
    """The items in consecutive lists of at most size."""
    return [items[i:i + size] for i in range(0, len(items), size)]


def list_lines(items, per_line):
    """Set data lines: the items joined by commas, per_line of them on each line."""
    return [", ".join(str(x) for x in chunk) for chunk in chunks(items, per_line)]


def element_lines(label, nodes, per_line):
    """An element's data lines: per_line numbers at most, continued after a trailing comma."""
    rows = list_lines([label] + nodes, per_line)
    return [row + "," for row in rows[:-1]] + rows[-1:]


def arithmetic_run(labels):
    """(first, last, step) when the labels are one increasing arithmetic run of 2 or more."""
    if len(labels) < 2 or not all(isinstance(x, int) for x in labels):
        return None
    step = labels[1] - labels[0]
    if step <= 0 or any(b - a != step for a, b in zip(labels, labels[1:])):
        return None
    return labels[0], labels[-1], step


def cased(text, upper):
    """A keyword line or a name as it is to be written: upper-cased with --upper."""
    return text.upper() if upper else text


def prepare(blocks):
    """Parses the data of the mesh blocks in place: elements, and members of sets."""
    for block in blocks:
        try:
            if block["keyword"] == "ELEMENT":
                block["elements"] = read_elements(block)
            elif block["keyword"] in ("ELSET", "NSET"):
                block["members"] = read_members(block)
        except (InpError, ValueError, IndexError) as err:
            raise InpError(f"line {block['lineno']} ({block['line']}): {err}") from None


def classify(blocks):
    """Sorts the elements: {label: nodes} of the volume elements (in file order) and
    {label: corners} of the face elements."""
    solids, faces = {}, {}
    for block in blocks:
        if block["keyword"] != "ELEMENT":
            continue
        etype = block["params"].get("TYPE", "")
        for label, nodes in block["elements"]:
            if solid_nodes(etype):
                solids[label] = nodes
            elif face_nodes(etype):
                faces[label] = nodes[:4 if face_nodes(etype) in (4, 8) else 3]
    return solids, faces


def surface_sets(blocks, elsets, faces):
    """The *ELSET names (upper case) whose members are all face elements, with their labels."""
    result = {}
    for block in blocks:
        if block["keyword"] != "ELSET" or "ELSET" not in block["params"]:
            continue
        name = set_name(block, "ELSET").upper()
        labels = unique(expand(name, elsets))
        in_faces = [label in faces for label in labels]
        if labels and all(in_faces):
            result[name] = labels
        elif any(in_faces):
            raise InpError(f"ELSET {name} mixes face elements with others")
    return result


def write_surface(out, name, labels, face_of, upper, per_line):
    """Writes the internal element sets and the *SURFACE of one set of face elements."""
    direct, by_face = [], {}
    for i, label in enumerate(labels):
        solid, k = face_of[label]
        if i % 2 == 0:
            direct.append((solid, k))
        else:
            by_face.setdefault(k, []).append(solid)
    internal = {k: cased(f"_{name}_S{k}", upper) for k in by_face}
    for k in sorted(by_face):
        out.append(cased(f"*ELSET, ELSET={internal[k]}", upper))
        out.extend(list_lines(by_face[k], per_line))
    out.append(cased(f"*SURFACE, NAME={name}, TYPE=ELEMENT", upper))
    out.extend(f"{solid}, S{k}" for solid, k in direct)
    out.extend(f"{internal[k]}, S{k}" for k in sorted(by_face))


def write_set(out, block, key, upper, per_line, generate):
    """Writes a kept *ELSET or *NSET block; GENERATE for an NSET run when generate is set.

    The keyword line is kept as read unless the set is rewritten (GENERATE, --upper).
    """
    name = cased(set_name(block, key), upper)
    members = [cased(m, upper) if isinstance(m, str) else m for m in block["members"]]
    run = arithmetic_run(members) if generate and key == "NSET" else None
    if run:
        out.append(f"*{key}, {key}={name}, GENERATE")
        out.append(f"{run[0]}, {run[1]}, {run[2]}")
        return
    if "GENERATE" in block["params"] or upper:
        out.append(f"*{key}, {key}={name}")
    else:
        out.append(block["line"])
    out.extend(list_lines(members, per_line))


def write_elements(out, block, upper, per_line):
    """Writes a kept *ELEMENT block (its keyword line as read, upper-cased with --upper)."""
    out.append(cased(block["line"], upper))
    for label, nodes in block["elements"]:
        out.extend(element_lines(label, nodes, per_line))


def write_all_sets(out, solids, nodes, taken, upper, per_line):
    """Writes NALL (when the node labels are 1..N) and EALL of the 3D elements (--generate),
    each unless its name is among the set names taken."""
    if "NALL" in taken or "EALL" in taken:
        print("inp_surfaces.py: NALL or EALL is in the deck already; not added again",
              file=sys.stderr)
    if "NALL" not in taken and nodes and nodes == list(range(1, len(nodes) + 1)):
        out.append(cased("*NSET, NSET=NALL, GENERATE", upper))
        out.append(f"1, {len(nodes)}, 1")
    labels = [] if "EALL" in taken else sorted(solids)
    if labels and labels == list(range(labels[0], labels[-1] + 1)):
        out.append(cased("*ELSET, ELSET=EALL, GENERATE", upper))
        out.append(f"{labels[0]}, {labels[-1]}, 1")
    elif labels:
        out.append(cased("*ELSET, ELSET=EALL", upper))
        out.extend(list_lines(labels, per_line))


def node_labels(blocks):
    """The sorted labels of the nodes of every *NODE block."""
    labels = set()
    for block in blocks:
        if block["keyword"] == "NODE":
            labels.update(int(tokens(line)[0]) for line in block["data"])
    return sorted(labels)


def convert(in_path, upper=False, generate=False, split_lines=False):
    """The rewritten deck of in_path as a list of lines."""
    blocks = read_blocks(in_path)
    prepare(blocks)
    solids, faces = classify(blocks)
    elsets = collect_elsets(blocks)
    surfaces = surface_sets(blocks, elsets, faces)
    face_of = find_faces({label: faces[label] for labels in surfaces.values()
                          for label in labels}, list(solids.items()))
    element_width, set_width = (8, 8) if split_lines else (16, 16)

    out = [f"** Written by inp_surfaces.py from {in_path}"]
    written = set()
    for block in blocks:
        keyword = block["keyword"]
        if keyword == "ELEMENT":
            if face_nodes(block["params"].get("TYPE", "")):
                continue
            write_elements(out, block, upper, element_width)
        elif keyword == "ELSET" and "ELSET" in block["params"]:
            name = set_name(block, "ELSET")
            if name.upper() in surfaces:
                if name.upper() not in written:
                    write_surface(out, name, surfaces[name.upper()], face_of, upper,
                                  set_width)
                    written.add(name.upper())
                continue
            write_set(out, block, "ELSET", upper, set_width, False)
        elif keyword == "NSET" and "NSET" in block["params"]:
            write_set(out, block, "NSET", upper, set_width, generate)
        else:
            out.append(cased(block["line"], upper))
            out.extend(block["data"])
    if generate:
        taken = set(elsets) | {set_name(b, "NSET").upper() for b in blocks
                               if b["keyword"] == "NSET" and "NSET" in b["params"]}
        write_all_sets(out, solids, node_labels(blocks), taken, upper, set_width)
    out.extend(TRAILER)
    return out


def main(argv):
    """Runs the command line; returns the exit status."""
    options = {"--upper", "--generate", "--split-lines"}
    flags = [a for a in argv if a.startswith("--")]
    paths = [a for a in argv if not a.startswith("--")]
    if len(paths) != 2 or not set(flags) <= options:
        print("usage: inp_surfaces.py IN.inp OUT.inp [--upper] [--generate] [--split-lines]",
              file=sys.stderr)
        return 2
    try:
        lines = convert(paths[0], upper="--upper" in flags, generate="--generate" in flags,
                        split_lines="--split-lines" in flags)
    except (InpError, OSError) as err:
        print(f"inp_surfaces.py: {paths[0]}: {err}", file=sys.stderr)
        return 1
    with open(paths[1], "w") as f:
        f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
