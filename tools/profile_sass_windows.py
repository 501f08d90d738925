"""Stall samples of one kernel by windows of its SASS (tools/profile_gpu.sh --sass).

Reads `ncu -i REPORT --page source --csv --print-source sass` and prints, per window of 250 instructions in
program order holding at least 1 % of the warp stall samples: the share, the warp instructions executed and the
threads per executed instruction; then the five instructions of the window with the most samples."""
import csv
import sys

WINDOW = 250


def main(path):
    rows = list(csv.reader(open(path)))
    header_at = next(i for i, row in enumerate(rows) if "Warp Stall Sampling (All Samples)" in row)
    header = rows[header_at]
    body = [row for row in rows[header_at + 1:] if len(row) == len(header)]
    col = {name: i for i, name in enumerate(header)}

    def number(row, name):
        text = row[col[name]].replace(",", "")
        return int(text) if text not in ("", "-") else 0

    samples = [number(r, "Warp Stall Sampling (All Samples)") for r in body]
    total = sum(samples) or 1
    print(f"{len(body)} instructions, {total} stall samples")
    print("window        samples  warp instructions  threads/instruction  hottest")
    for start in range(0, len(body), WINDOW):
        window = range(start, min(start + WINDOW, len(body)))
        share = sum(samples[i] for i in window) / total
        if share < 0.01:
            continue
        executed = sum(number(body[i], "Instructions Executed") for i in window)
        threads = sum(number(body[i], "Thread Instructions Executed") for i in window)
        hottest = sorted(window, key=lambda i: -samples[i])[:5]
        names = ", ".join(body[i][col["Source"]].split()[0 if not body[i][col["Source"]].strip().startswith("@") else 1]
                          for i in hottest)
        print(f"{start:5d}-{window[-1]:5d} {100 * share:6.1f} % {executed:18d} {threads / max(executed, 1):20.1f}  {names}")


if __name__ == "__main__":
    main(sys.argv[1])
