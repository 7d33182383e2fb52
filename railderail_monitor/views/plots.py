"""The time-series views every tab of the Rerun views shares (rerun_views, planning, sensor_tab): the two
timelines and a plot that shows the run so far."""
import rerun.blueprint as rrb

TIMELINE = "sim_time"
POSITION = "track_position_mm"             # Rerun's sequence timelines are integers: mm keeps every sample apart
# every plot shows the run so far, from its start to the time cursor: the data it draws and the x range it
# opens with (else a plot of a long run opens zoomed on a few seconds)
SO_FAR = dict(start=rrb.TimeRangeBoundary.infinite(), end=rrb.TimeRangeBoundary.cursor_relative())


def plot(origin, name, contents="$origin/**", legend=True):
    return rrb.TimeSeriesView(origin=origin, name=name, contents=contents,
                              time_ranges=[rrb.VisibleTimeRange(line, **SO_FAR) for line in (TIMELINE, POSITION)],
                              axis_x=rrb.TimeAxis(view_range=rrb.TimeRange(**SO_FAR)),
                              plot_legend=rrb.PlotLegend(corner=rrb.Corner2D.LeftTop, visible=legend))
