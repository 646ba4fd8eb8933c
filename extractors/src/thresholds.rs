//! Every threshold the extractors use, named and documented in one place.
//!
//! The values follow the reference behaviour of RefAV's atomic functions
//! (`refAV/atomic_functions.py` in the RefAV repository) unless a comment says otherwise.
//! Distances are metres, speeds m/s, angles degrees, times frames or seconds as named.
//!
//! Sections: kinematics, lanes and map, events, then the pairwise relations (appended by the pairs
//! work at the end of the file; keep new constants inside their section).

// ---------------------------------------------------------------------------------------------
// Kinematics
// ---------------------------------------------------------------------------------------------

/// Window (frames of 0.1 s, odd) of the median filter over positions and their derivatives; a
/// track sampled less often uses the same span of time in samples (`kinematics::median_window`:
/// 7 at 10 Hz, 1 at 2 Hz). Tracks shorter
/// than this use the largest odd window that fits; at a track's ends the window is truncated to
/// the boxes that exist (no zero padding, which pulled RefAV's end values towards 0).
pub const MEDIAN_WINDOW: usize = 7;

/// A track is `stationary` when the diagonal of the bounding box of its smoothed positions over
/// its whole life is below this (parked, not merely stopped).
pub const STATIONARY_MAX_DIAGONAL_M: f64 = 3.0;

// ---------------------------------------------------------------------------------------------
// Lanes and map
// ---------------------------------------------------------------------------------------------

/// A lane counts as turning left/right (for breaking lane-assignment ties against the track's mean
/// yaw rate) when its centreline's heading changes by more than this from start to end.
pub const LANE_TURN_MIN_DEG: f64 = 20.0;

/// `lane_turn`: a lane segment takes its traffic left or right when its centre line's heading
/// changes by more than this from its start to its end (the angle `turning` asks of a track);
/// AV2's turning intersection lanes turn 60-100°, its straight ones less than 20°.
pub const LANE_TURN_CLASS_DEG: f64 = 45.0;

/// A track counts as turning left/right (for lane-assignment ties) when its mean yaw rate over the
/// candidate run exceeds this, deg/s.
pub const TRACK_TURN_MIN_YAW_RATE_DEG_S: f64 = 3.0;

/// In the lane as a driver sees it, a successor (predecessor) continues the lane when it is the
/// only one, or when it is the straightest and both its own heading change and the angle at the
/// joint stay under this.
pub const LANE_CHAIN_STRAIGHT_MAX_DEG: f64 = 30.0;

/// How far (centreline length) the lane chain reaches beyond the lane itself in each direction.
/// Pairs never exceed 50 m, so a little more than that is enough.
pub const LANE_CHAIN_REACH_M: f64 = 60.0;

/// Most lane segments the lane chain holds beyond the lane itself in each direction: far more than
/// [`LANE_CHAIN_REACH_M`] of real lanes (segments are metres long), a bound for maps of
/// near-zero-length lanes, whose chains would otherwise grow with the map.
pub const LANE_CHAIN_MAX_SEGMENTS: usize = 128;

/// Map distances (`near_intersection`, `at_crosswalk`) are produced only up to this distance; a
/// farther object has no tuple. RefAV's own defaults are 5 m and 1 m, well inside.
pub const MAP_DISTANCE_MAX_M: f64 = scenalog_facts::catalog::MAP_RANGE_M;

/// `at_stop_sign`: X's centre lies at most this far before the stop sign, measured along X's
/// forward axis (RefAV's `forward_thresh`).
pub const STOP_SIGN_FORWARD_MAX_M: f64 = 10.0;

/// `at_stop_sign`: the stop sign's lane is the nearest lane, within this distance of the sign, whose
/// direction of travel has the sign on its right-hand side (or under it).
pub const STOP_SIGN_LANE_SEARCH_M: f64 = 10.0;

/// `at_stop_sign`: X faces the sign when its heading is within this angle of its lane's direction
/// at the sign (so the sign is ahead of it, not behind).
pub const STOP_SIGN_HEADING_MAX_DEG: f64 = 45.0;

/// `at_stop_sign`: the sign may be at most this far to the side of X's forward axis.
pub const STOP_SIGN_LATERAL_MAX_M: f64 = 10.0;

// ---------------------------------------------------------------------------------------------
// Events
// ---------------------------------------------------------------------------------------------

/// `turning`: a run of same-sign yaw rate is a turn when the heading changes by more than this over
/// the run.
pub const TURN_MIN_ANGLE_DEG: f64 = 45.0;

/// `turning`: yaw rates of at most this magnitude (deg/s, after the median filter) are "no turn"
/// and end a run, so sensor jitter on a straight road does not chain unrelated bends together.
pub const TURN_DEAD_BAND_DEG_S: f64 = 1.0;

/// `lane_change`: the velocity component across the crossed boundary, towards the new lane, must be
/// at least this (m/s) when the centre changes lanes.
pub const LANE_CHANGE_MIN_LATERAL_SPEED: f64 = 0.1;

/// `lane_change`: the velocity must run roughly along the crossed boundary: |cos| of the angle
/// between them at least this.
pub const LANE_CHANGE_MIN_ABS_COS: f64 = 0.5;

/// `lane_change`: the span covers the frames whose offset across the crossed boundary keeps growing
/// towards the new lane at [`LANE_CHANGE_MIN_LATERAL_SPEED`] or more, while the offset lies within
/// this many lane widths of the boundary on either side (0.5: from the old lane's centre to the new
/// one's).
pub const LANE_CHANGE_SPAN_WIDTHS: f64 = 0.5;

// ---------------------------------------------------------------------------------------------
// Pairs (the pairs work appends its constants below this line)
// ---------------------------------------------------------------------------------------------

/// Pairs are produced only when the two boxes' ground rectangles are at most this far apart
/// (every pair relation; RefAV's `within_distance` / `max_distance` default).
pub const PAIR_MAX_DISTANCE_M: f64 = scenalog_facts::catalog::PAIR_RANGE_M;

/// `heading_relative`: "same" when the angle between the two headings is at most this.
pub const HEADING_SAME_MAX_DEG: f64 = 45.0;

/// `heading_relative`: "opposite" when the angle between the two headings is at least this;
/// strictly between [`HEADING_SAME_MAX_DEG`] and this is "perpendicular".
pub const HEADING_OPPOSITE_MIN_DEG: f64 = 135.0;

/// `heading_relative`: an object at least this fast (m/s) is headed along its velocity; a slower
/// one along its box heading if it moves by itself, and has no heading otherwise.
pub const HEADING_MIN_SPEED_M_S: f64 = 1.0;

/// `facing`: Y's centre lies within this angle of X's forward axis (either side).
pub const FACING_MAX_ANGLE_DEG: f64 = 22.5;

/// `heading_toward`: X's velocity points within this angle of the direction to Y's centre.
pub const HEADING_TOWARD_MAX_ANGLE_DEG: f64 = 22.5;

/// `heading_toward`: X closes on Y (the distance between the centres shrinks) at least this fast,
/// m/s (RefAV measured it per frame; this is per second).
pub const HEADING_TOWARD_MIN_CLOSING_M_S: f64 = 0.5;

/// `heading_toward`: X itself moves at least this fast (m/s), so its velocity has a direction.
pub const HEADING_TOWARD_MIN_SPEED_M_S: f64 = 0.5;

/// `crossing`: the half-midplane extends this far beyond X's Dir side (RefAV's `forward_thresh`).
pub const CROSSING_REACH_M: f64 = 10.0;

/// `crossing`: the event spans the frames while Y's centre is within this distance of the
/// midplane (either side; RefAV's `lateral_thresh`, which it only bounded on the far side).
pub const CROSSING_SPAN_M: f64 = 5.0;

/// `crossing_detail`: crossings are found up to this far beyond X's Dir side (the `Reach` column
/// is at most this; RefAV programs pass `forward_thresh` 1-20 m).
pub const CROSSING_DETAIL_MAX_REACH_M: f64 = 30.0;

/// `crossing_detail`: the event spans the frames while Y's centre is within this distance of the
/// midplane (the `Off` column is at most this; RefAV programs pass `lateral_thresh` 2-10 m).
pub const CROSSING_DETAIL_MAX_OFF_M: f64 = 15.0;

/// `crossing`: Y moves across the midplane, relative to X, faster than this (m/s), at the crossing
/// and at every frame of the span.
pub const CROSSING_MIN_SPEED_M_S: f64 = 0.2;

/// `following`: the lead's centre lies ahead of X's front by more than 0 and less than this.
pub const FOLLOWING_MAX_AHEAD_M: f64 = 25.0;

/// `following`: the lead's centre lies less than this far to either side of X's forward axis.
pub const FOLLOWING_MAX_LATERAL_M: f64 = 5.0;

/// `following`: cosine of the angle between the two headings above this (60°).
pub const FOLLOWING_MIN_HEADING_COS: f64 = 0.5;

/// `following`: an object faster than this (m/s) is headed along its velocity, a slower one along
/// its box heading.
pub const FOLLOWING_HEADING_MIN_SPEED_M_S: f64 = 0.5;

// ---------------------------------------------------------------------------------------------
// Concepts descriptions name (towing, in_between, lane_direction; issue #14). RefAV has no atomic
// function for any of them: the values are the ones RefAV's own scenario programs pass to
// `has_objects_in_relative_direction` when they approximate the concept.
// ---------------------------------------------------------------------------------------------

/// `towing`: at most this gap (m) between the towing vehicle's and the trailer's ground
/// rectangles (RefAV's "truck without trailer" program: `within_distance=3`, "trailers should be
/// directly attached").
pub const TOWING_MAX_GAP_M: f64 = 3.0;

/// `towing`: the trailer's centre lies at most this far (m) outside the towing vehicle's sides
/// (the same program: `lateral_thresh=2`, "some lateral offset for turning").
pub const TOWING_MAX_LATERAL_M: f64 = 2.0;

/// `towing`: the two box headings differ by at most this (degrees): a trailer swings behind a
/// turning cab, but one standing across the cab's rear is not in tow.
pub const TOWING_MAX_HEADING_DEG: f64 = 60.0;

/// `in_between`: both outer objects are at most this far (m, box to box) from the one between
/// them (RefAV's "motorcycle between two vehicles" program: `within_distance=5`).
pub const BETWEEN_MAX_GAP_M: f64 = 5.0;

/// `in_between`: the middle object's centre lies at most this far (m) from the segment joining the
/// outer objects' centres (the same program: `lateral_thresh=2`).
pub const BETWEEN_MAX_OFFSET_M: f64 = 2.0;

/// `lane_direction`: an object at least this fast (m/s) travels along its velocity, a slower one
/// along its box heading (as `heading_relative`, [`HEADING_MIN_SPEED_M_S`]).
pub const LANE_DIRECTION_MIN_SPEED_M_S: f64 = HEADING_MIN_SPEED_M_S;
