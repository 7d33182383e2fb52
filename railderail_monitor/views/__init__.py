"""The views: Rerun (`rerun_views`, the live viewer node `viewer_node`) and the Foxglove layout's sensors tab
(`foxglove`). They compute nothing of their own beyond what the monitor and the estimator give."""
