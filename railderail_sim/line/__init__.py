"""The line as data: its curves, speed limits, known track defects and wind-measurement sites by position
(`data`), and its YAML file (`file`; the shipped lines in railderail_sim/config/lines/). Import the modules
themselves: this file imports nothing."""
