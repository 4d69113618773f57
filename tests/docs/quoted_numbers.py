"""Numbers a page quotes from a run, compared with the run's values (tests/docs/check_*.py)."""


def same_to_printed_digits(printed, value):
    """True when `value` rounded to the decimals of `printed` (a string such as "0.0562" or
    "+0.193") is that number: a page's number is right when it is the run's value as printed."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return abs(float(printed) - value) <= 0.5 * 10**-decimals + 1e-12


class Tally:
    """The numbers checked and the differences found, printed at the end."""

    def __init__(self):
        self.checked = 0
        self.problems = []

    def number(self, what, printed, value):
        self.checked += 1
        if not same_to_printed_digits(printed, value):
            self.problems.append(f"{what}: the page says {printed}, the run gives {value:.6g}")

    def problem(self, text):
        self.problems.append(text)

    def finish(self, what):
        """Prints each difference and the count; returns the exit status."""
        for p in self.problems:
            print("MISMATCH", p)
        print(f"{what}: {self.checked} numbers checked, {len(self.problems)} differ")
        return 1 if self.problems else 0
