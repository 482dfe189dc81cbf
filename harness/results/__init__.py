"""Results on disk: the run journal, JSON and JUnit output, the CI gate, run diffs, and the
atomic writes and schema checks they share."""
