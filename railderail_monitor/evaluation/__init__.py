"""The warning evaluation: which criterion warns, how early, how usefully and how often falsely, over the
paper's radii (`over_radii`, `railderail warnings`) or a scenario catalogue (`catalogue`, the scenario file;
`hazards`, the ground truth by hazard and the braking model; `scoring`, attribution, exposure and intervals;
`over_catalogue`, the evaluation, with `sweeps`, `catalogue_runs`, `tables`, `recommendation`, `sensitivities`
and `supervision_score`; `report`, their markdown), and the on-board instability rules' speed sweep
(`onboard_study`)."""
