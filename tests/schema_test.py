#!/usr/bin/env python3
"""Every graph under graphs/ and every graph example in docs/*.md validates
against docs/graph.schema.json, and documents the parser refuses for their
structure are refused by the schema too, so the schema cannot drift from the
parser. Usage: schema_test.py SOURCE_DIR LOOM_RUNNER"""
import json, pathlib, re, subprocess, sys, tempfile

try:
    import jsonschema
except ImportError:
    print("python3-jsonschema is not installed (scripts/install-deps installs it)")
    sys.exit(77)

source, runner = pathlib.Path(sys.argv[1]), sys.argv[2]
schema = json.loads((source / "docs/graph.schema.json").read_text())
validator = jsonschema.Draft202012Validator(schema)
failures = []

graphs = sorted((source / "graphs").glob("*.json")) + sorted((source / "graphs" / "lib").glob("*.json"))
for path in graphs:
    for error in validator.iter_errors(json.loads(path.read_text())):
        failures.append(f"{path.name}: {'/'.join(map(str, error.path))}: {error.message}")

examples = 0
for md in sorted((source / "docs").glob("*.md")):
    for block in re.findall(r"```json\n(.*?)```", md.read_text(), re.S):
        try:
            doc = json.loads(block)
        except json.JSONDecodeError:
            continue  # a fragment, not a document
        if isinstance(doc, dict) and "loom" in doc:
            examples += 1
            for error in validator.iter_errors(doc):
                failures.append(f"{md.name} example: {'/'.join(map(str, error.path))}: {error.message}")

# Structurally wrong documents: the parser says exit 2, the schema says invalid.
node = {"type": "FloatConstant"}
wrong = {
    "no version": {"nodes": {}},
    "version 3": {"loom": 3, "nodes": {}},
    "groups in version 1": {"loom": 1, "groups": {}, "nodes": {}},
    "Repeat without body": {"loom": 2, "nodes": {"r": {"type": "Repeat"}}},
    "body on another node": {"loom": 2, "nodes": {"a": dict(node, body="G")}},
    "interface input without to": {"loom": 2, "inputs": {"x": {"type": "Float"}}, "nodes": {}},
    "unknown top key": {"loom": 1, "nodes": {}, "extra": 1},
    "negative seed": {"loom": 1, "seed": -1, "nodes": {}},
    "nodes not an object": {"loom": 1, "nodes": []},
    "dot in id": {"loom": 1, "nodes": {"a.b": node}},
    "node without type": {"loom": 1, "nodes": {"a": {"inputs": {}}}},
    "unknown node key": {"loom": 1, "nodes": {"a": dict(node, extra=1)}},
    "inputs not an object": {"loom": 1, "nodes": {"a": dict(node, inputs=[])}},
    "link without dot": {"loom": 1, "nodes": {"a": dict(node, inputs={"value": {"from": "b"}})}},
    "link with extra key": {"loom": 1, "nodes": {"a": dict(node, inputs={"value": {"from": "b.value", "x": 1}})}},
}
with tempfile.TemporaryDirectory() as tmp:
    for name, doc in wrong.items():
        schema_ok = validator.is_valid(doc)
        path = pathlib.Path(tmp) / "g.json"
        path.write_text(json.dumps(doc))
        rc = subprocess.run([runner, "validate", str(path)], capture_output=True).returncode
        if schema_ok or rc != 2:
            failures.append(f"'{name}': schema {'accepts' if schema_ok else 'refuses'}, loom validate exits {rc}")

print(f"{len(graphs)} graphs, {examples} doc examples, {len(wrong)} wrong documents checked")
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
