"""Writes the grader's verdict as the GitHub Actions job summary: a Markdown
table of the graded functions (and the sequence stage) with their points (one per counted case) and
the first failure of each, or the compiler's errors when the code does not
build. Appends to $GITHUB_STEP_SUMMARY (and prints the same). Exits 0 when
every counted case passed, 1 otherwise, so that the check is green or red.

Usage: summary.py BUILD_LOG REPORT_JSON"""

import json
import os
import sys

def cell(text):
    """Text for one table cell: on one line, pipes escaped, in a code span
    whose fence no backtick inside can close."""
    text = " ".join(text.split()).replace("|", "\\|")
    if not text:
        return ""
    fence = "`"
    while fence in text:
        fence += "`"
    return f"{fence} {text} {fence}"


def block(text):
    """A fenced block that no line of `text` can close."""
    fence = "```"
    while fence in text:
        fence += "`"
    return f"{fence}text\n{text}\n{fence}"


def compiler_errors(build_log):
    """The compiler's errors (each `error...` line and what follows it up to
    a blank line), at most 40 lines."""
    try:
        lines = open(build_log, encoding="utf-8", errors="replace").read().splitlines()
    except OSError:
        return ""
    out, inside = [], False
    for line in lines:
        if line.startswith("error"):
            inside = True
        if inside:
            out.append(line)
            if not line.strip():
                inside = False
    return "\n".join(out[:40])


def summary(build_log, report_path):
    """The Markdown summary and whether every counted case passed."""
    try:
        report = json.load(open(report_path, encoding="utf-8"))
        cases = [c for c in report["cases"] if c["group"] != "bonus" or report["bonus_counted"]]
        # The grader's stages in grading order, as its JSON names them
        # (key) and as the table names them (title): the grader's one list.
        stages = [(s["key"], s["title"]) for s in report["stages"]]
    except (OSError, ValueError, KeyError, TypeError):
        report, cases = None, []
    if report is None or not cases:
        errors = compiler_errors(build_log)
        text = "## Mesh lab: not graded\n\n"
        if errors:
            text += "The code does not compile:\n\n" + block(errors) + "\n"
        else:
            text += "The grader did not finish: run `cargo run -p grader` and read its messages.\n"
        return text, False
    rows, total, got = [], 0, 0
    for stage, function in stages:
        mine = [c for c in cases if c["stage"] == stage]
        passed = sum(1 for c in mine if c["passed"])
        first = next((c for c in mine if not c["passed"]), None)
        failure = ""
        if first is not None:
            # The grader's own one-line form: student text in it is escaped.
            failure = f"{first['name']}: {first.get('first_warning') or 'failed'}"
        if not mine:
            continue
        rows.append(f"| `{function}` | {passed}/{len(mine)} | {cell(failure)} |")
        total, got = total + len(mine), got + passed
    verdict = "all tests passed" if got == total else "test failed"
    text = (f"## Mesh lab: {got}/{total} points, {verdict}\n\n"
            "| function | points | first failure |\n|---|---|---|\n" + "\n".join(rows) + "\n")
    if got != total:
        text += "\nRun `cargo run -p grader` for every message and the next command to run.\n"
    return text, got == total


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    text, passed = summary(sys.argv[1], sys.argv[2])
    target = os.environ.get("GITHUB_STEP_SUMMARY")
    if target:
        with open(target, "a", encoding="utf-8") as f:
            f.write(text)
    print(text)
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
