"""The paper's learners and the baselines (a later issue)."""
