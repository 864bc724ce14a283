"""Every repository path that README.md and docs/*.md name in code (fenced
blocks and `inline code`) exists: `graphs/groups-*.json` must match a file,
`docs/farm.md` must be there. Paths under build/, out/ and other generated
folders (bench/results/, written by scripts/bench) are not checked, nor the
files of a plugin `loom new-plugin` writes (docs/plugin-authoring.md names
them inside the new plugin's folder). Usage: paths_test.py SOURCE_DIR."""
import glob
import os
import re
import sys

SOURCE = sys.argv[1]
TOP = ("graphs/", "docs/", "scripts/", "engine/", "plugins/", "tests/", "bench/", "python/", "editor/", "cmake/",
       "fuzz/", ".ci/")
TOKEN = re.compile(r"[A-Za-z0-9_./*{}\-]+")


def code_spans(text):
    for block in re.findall(r"```.*?\n(.*?)```", text, re.S):
        yield block
    for span in re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S)):
        yield span


def named_paths(text):
    for span in code_spans(text):
        for token in TOKEN.findall(span):
            token = token.rstrip(".,:;)")
            if token.startswith(TOP) and not token.startswith("bench/results") and "{" not in token:
                yield token


def main():
    files = [os.path.join(SOURCE, "README.md")] + sorted(glob.glob(os.path.join(SOURCE, "docs", "*.md")))
    missing, checked = [], 0
    for doc in files:
        if doc.endswith("plugin-authoring.md"):  # paths inside a new plugin's own folder
            continue
        with open(doc) as f:
            text = f.read()
        for path in sorted(set(named_paths(text))):
            checked += 1
            if not glob.glob(os.path.join(SOURCE, path)):
                missing.append(f"{os.path.relpath(doc, SOURCE)}: {path}")
    for m in missing:
        print("missing:", m)
    print(f"paths: {checked - len(missing)} passed, {len(missing)} failed")
    sys.exit(1 if missing else 0)


if __name__ == "__main__":
    main()
