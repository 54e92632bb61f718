"""MuJoCo against the closed form: tolerances, comparison, diagnosis of failures, the cost of
practical settings and the report."""
