"""railderail monitor: derailment criteria, early warning, recording and replay."""
