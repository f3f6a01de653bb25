"""The motion layer's defaults, in one record (SI units: m, s, N, rad).

Every primitive of :mod:`oacdsl.runtime.motion` takes its speeds, distances, forces and
times from a :class:`Tuning`; a skill that needs another value says so by name
(``TUNING.hover_m``) or passes one, never by a literal of its own. Nothing here refers to
how a run is judged (the verifier has its own thresholds, and no skill imitates them).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Tuning", "TUNING"]


@dataclass(frozen=True)
class Tuning:
    """Defaults of the motion primitives (see the field comments)."""

    # --- carry: along a path over the objects near the way ---------------------------------
    #: time of a carry (climb, across, down) when it is short, s
    carry_s: float = 1.6
    #: mean speed a long carry is timed by, m/s (faster, the arm swings and the wrist feels it)
    carry_speed_m_s: float = 0.25
    #: share of a carry's time spent climbing first, when it must climb
    climb_share: float = 0.4
    #: obstacles whose footprint comes this close to the way are flown over, m
    near_path_m: float = 0.12
    #: room kept above what is flown over, m
    over_m: float = 0.03
    #: how far from its start a carry may first move at its height to be out from under what
    #: the other hand holds up (tried nearest first), m (motion/detour.py)
    detour_steps_m: tuple[float, ...] = (0.06, 0.12, 0.18, 0.24)
    #: a still moment after a carry, before a guarded approach starts, s
    pause_s: float = 0.1
    #: a still moment after carrying something to where it is set down, s
    carry_pause_s: float = 0.2
    #: time of a carry to where a tool starts working (over a container or surface), s
    work_carry_s: float = 1.8

    # --- guarded approach: until contact or force ------------------------------------------
    #: height above what is approached before the approach, m
    hover_m: float = 0.04
    #: the shortest approach a grasp from the side keeps when its pre-grasp is moved in, off a
    #: neighbouring object, m (the planned one: ``grasping.PRE_GRASP_M``)
    pre_grasp_min_m: float = 0.08
    #: the step by which such a pre-grasp is moved in, m
    pre_grasp_step_m: float = 0.02
    #: peak speed of an approach of one object to another, m/s
    approach_speed_m_s: float = 0.08
    #: peak speed of setting a held object down on a support, m/s (a 0.6 kg mixer meeting the
    #: table at twice that gave a 66 N spike within one control tick)
    set_down_speed_m_s: float = 0.05
    #: wrist force change that means "the support took the object", N
    support_force_n: float = 3.0
    #: wrist force change that stops an approach aiming at a contact: something else is in the way, N
    obstacle_force_n: float = 8.0
    #: how long a stopped approach may still wait for the contact it aimed at, s
    contact_wait_s: float = 0.3
    #: how far below a support's top a set-down may go looking for it, m
    support_search_m: float = 0.03
    #: how far above the surface under it a set-down object that touches its support may be
    #: and still rest on it (the wrist felt nothing: the arm stalled), m
    rest_gap_m: float = 0.005
    #: how far inside an object's end a tool aims when it works at that end, m (a knife on a
    #: cucumber's free end; strokes along a board stop short of its edge)
    end_margin_m: float = 0.01
    #: how far a stroking hand stays from what the other hand holds (its collision boxes, m)
    hand_clearance_m: float = 0.02

    #: room left between a held object and a wall it is slid against, m
    gap_m: float = 0.003
    #: time of a short shift of a held object (a few centimetres), s
    shift_s: float = 0.6
    #: how far a held object is moved to its hand's side, out of the way of the other hand, m
    aside_m: float = 0.10

    # --- tools in containers ---------------------------------------------------------------
    #: room kept between a tool and a container's inner wall (or another tool), m
    wall_margin_m: float = 0.005
    #: free space kept between a hand and a container's rim, m
    rim_clearance_m: float = 0.015
    #: free space kept between the collision boxes of a hand working right over the other hand
    #: (pouring into the cup it holds; the arm follows the tilt within a few mm there) and that
    #: hand's, m (as ``FOLLOW.hand_clearance_m``)
    hands_clearance_m: float = 0.01
    #: a round source (no spout) is turned about its axis before a pour, by up to
    #: ``pour_turn_most_rad`` either way in steps of ``pour_turn_step_rad`` (90°, 15°), when the
    #: turn lets its lip roll the balls out at least ``pour_turn_gain_m`` lower: its hand then
    #: reaches less over the target and the other hand holding it
    pour_turn_most_rad: float = 1.5708
    pour_turn_step_rad: float = 0.2618
    pour_turn_gain_m: float = 0.01
    #: fastest change of the extra lift a pour's lip is given for the arm's measured lag, m/s
    #: (up or down, over the planned path). The lag is measured against the raised goal, so an
    #: unbounded lift fed itself: a step up made the arm lag by as much, which asked for more;
    #: on the dough (seed 3) the lip's goal rose 9 cm and fell again within 0.12 s, the cup's
    #: jerk threw the balls up in it, and one left the lip at 1.1 m/s, over the bowl's far rim.
    #: 0.1 m/s is 2 mm per control tick, at most 1.5 cm over the 0.15 s the arm takes to catch up
    #: with a step, and keeps the cup's vertical acceleration well under g (the balls stay on
    #: its wall)
    pour_lift_speed_m_s: float = 0.1
    #: where a tool goes down into a container beside the balls lying there: points on rings
    #: ``free_spot_step_m`` apart round its middle, ``free_spot_turn_rad`` apart round each (1 cm, 30°)
    free_spot_step_m: float = 0.01
    free_spot_turn_rad: float = 0.5236
    #: height of a tool's tip above a rim before it goes in, m
    above_rim_m: float = 0.05
    #: how far beyond a wall (or into a floor) a tool is aimed to stay in contact with it, m
    aim_beyond_m: float = 0.005
    #: how far below a rim a tool's tip must reach to work in a container, m
    min_inside_m: float = 0.02
    #: steps in which a tool leaned about its head in a container is checked for its hand
    #: meeting the rim, rad (about 3°)
    lean_step_rad: float = 0.05

    # --- rotate about an axis, regrasping ---------------------------------------------------
    #: close enough to the wanted turn to stop, rad
    turn_enough_rad: float = 0.14
    #: most strokes, as a multiple of those the turn needs (a stroke turns the object some 10 %
    #: less than the hand, a regrasp turns it back a few degrees: more strokes make it up)
    turn_strokes_factor: int = 2
    #: shortest time of one stroke, s
    turn_min_stroke_s: float = 0.6
    #: about what a regrasp takes (open, rise, turn back, come down, close), s
    turn_regrasp_s: float = 2.1
    #: time to turn the open hand back, s
    turn_back_s: float = 0.5
    #: how far below where it let go the palm is aimed while the fingers open, m
    turn_hold_down_m: float = 0.005
    #: how far the grasp centre may be off the object's axis before the first stroke, m
    #: (farther, the hand first retakes it on the axis: a lid taken 4 cm off swung the hand round)
    turn_off_axis_m: float = 0.015
    #: how far down an object that lost the target is set on it before the hand lets go, m
    turn_seat_m: float = 0.01
    #: how far the object's axis may be off the target's when the hand lets go of it, m
    turn_centred_m: float = 0.005
    #: a turned object whose shape is farther than this from the target's has left its seat:
    #: the stroke stops and it is set back on (a stroke the arm could not follow lifted a lid
    #: 6–17 mm off its bottle and went on turning it in the air), m
    turn_unseated_m: float = 0.003
    #: two objects nearer than this are judged by the simulation's distance between their
    #: shapes, not their bounding boxes (the box of a lid held 6° tilted reaches 2 mm below its
    #: rim: "pressed" by its box, it hung 0.2 mm over the bottle), m
    gap_measured_within_m: float = 0.05
    #: an object whose lowest point is no more than this below another's top rests on it
    #: (``place`` centres it there on an open container's rim), m
    cover_slack_m: float = 0.01
    #: most moves that bring the object back onto the target's axis, and the time of each, s
    turn_centre_tries: int = 4
    turn_centre_s: float = 0.25
    #: how much of the next stroke a hand taking the object again may be turned back first
    #: (shares of the stroke), and by how much (m of IK error, the angle counted 0.1 m/rad) a
    #: pose turned back further may be reached worse than the best one and still be chosen
    turn_wind_back_share: tuple[float, ...] = (0.0, 0.25, 0.5, 0.75, 1.0)
    turn_wind_back_gain_m: float = 0.002

    # --- arm postures --------------------------------------------------------------------------
    #: room kept between an arm's links (upper arm to wrist) and the table or the objects in a
    #: posture a skill chooses among others (the IK does not see them), m
    arm_room_m: float = 0.02
    #: solver steps a static solve of a pose may take (the IK settling there before a motion)
    pose_solve_tries: int = 150

    # --- tip a held object over a container --------------------------------------------------
    #: how many horizontal axes (evenly round) a tip is tried about; the best reached is taken
    tip_axis_tries: int = 8
    #: how many poses along a tip are checked for the tool's clearance from the other hand
    tip_pose_tries: int = 5

    # --- free spots on the table ------------------------------------------------------------
    #: spacing of the candidate spots, m, and the room kept between footprints there, m
    spot_step_m: float = 0.04
    spot_gap_m: float = 0.04
    #: the forearm seen from above (its last part before the hand), kept clear of other
    #: footprints at a free spot, m
    forearm_m: float = 0.3
    #: free spots (and turns) judged by the IK's postures there, best first, at most
    spot_tries: int = 40
    #: turns about its axis a round object may be set down with on a free spot, the hand
    #: turning with it (so it stands on another side and withdraws another way), rad; as held first
    spot_turns_rad: tuple[float, ...] = (0.0, -0.52, 0.52, -1.05, 1.05, -1.57, 1.57)
    #: a place the demonstration set an object down on: spots within this of it are tried
    #: (nearest first; none passing: as when there is none), m; and nearer than this to where
    #: it was picked up, it goes back there (the person put it back), m
    demo_spot_within_m: float = 0.08
    demo_spot_back_m: float = 0.05

    # --- set down turned as demonstrated (touch's tilt) ---------------------------------------
    #: a held object is turned to the demonstrated end tilt only when it is held farther from it
    #: than this, rad (a cup held upright, demonstrated 1-5° off, is brought down as it is held)
    reorient_min_rad: float = 0.5
    #: turns about its own axis tried for a round object set on edge (or horizontal tilt axes round
    #: the compass), and for any other object set into a slot (it fits one way of four)
    stand_spin_tries: int = 12
    stand_square_spin_tries: int = 4
    #: wrist force change that stops a descent into a slot, N, unless the skill's own is higher (a
    #: plate hanging from its rim pulled the wrist by 8 N as it went down, touching nothing)
    slot_force_n: float = 20.0
    #: solver steps of the static solve that finds how far the IK settles short of a hand kept
    #: where it is (``Motion.stay``; a whole-body reach check takes 150)
    stay_solve_tries: int = 150
    #: a still moment after a carry that turned the held object, s (an arm that turned a 0.4 kg
    #: plate on edge lagged its command by centimetres, and went down from there onto a wall)
    turn_settle_s: float = 1.0
    #: poses along a turn in place, and solver steps at each, from which the joints' travel
    #: through it is found (``touch``'s turn of an object set on edge)
    turn_sample_tries: int = 9
    turn_solve_tries: int = 40

    # --- press -----------------------------------------------------------------------------
    #: how far a held object is pressed on once it touches, m
    press_m: float = 0.003
    #: time of a press, s
    press_s: float = 0.2
    #: how far below where it touched a held tool is kept while it moves along a surface, m
    #: (a light touch: pressed 2 mm while circling, a salad server shifted in the hand's weld
    #: and the fingers lost its handle; not pressed, its contact flickered: KIT Mix)
    slide_press_m: float = 0.001
    #: how much of a stroke's press over that light one is eased on the stroke's way back on the
    #: surface (``Motion.slide_back``; eased to the light press, the peeler sprang off the
    #: cucumber for 0.2 s; not eased, it chattered on it for 0.5 s: synthetic Peel, seed 0)
    slide_back_ease_share: float = 0.5
    #: force a tool is kept pressed on a surface with while it moves along it (a press
    #: regulated on the wrist's measured force, ``motion.press.ForcePress``), N
    press_force_n: float = 10.0
    #: how fast the regulated press lowers (or raises) the hand per newton it lacks (or has
    #: too much), m/s per N (at most the seek speed); and the share of a new force reading taken
    #: into its filtered value at each control tick
    press_gain_m_per_n_s: float = 0.001
    press_filter_share: float = 0.3
    #: the share of that rate the press rises at when it presses too hard (a peak of force
    #: that passes is better borne than followed up: risen after it, the tool left the surface)
    press_ease_share: float = 0.25
    #: how far below (and above) its path the regulated press may aim the hand, m
    press_depth_max_m: float = 0.008
    press_rise_max_m: float = 0.004

    #: how many times a hand about to let go of an object pressed on a support raises its goal
    #: to where it really is (``Motion.ease``: each about halves the press)
    ease_tries: int = 3

    # --- rise / lift -----------------------------------------------------------------------
    #: how far a held object is lifted off what it touches, m
    lift_m: float = 0.12
    #: time of a lift, s
    lift_s: float = 1.0
    #: a reach of both hands at once is slowed by these factors in turn until the whole-body IK
    #: keeps each hand within the reach tolerance of its way; else the hands reach one after the
    #: other (``grasp_both``)
    pace_factor: tuple[float, ...] = (1.0, 1.5, 2.0, 3.0)
    #: a still moment after a lift or before a release, s (the arm, which lags its command,
    #: comes to rest: a knife let go while still pressing 9 N tipped over)
    settle_s: float = 0.3

    # --- grasp, release and withdrawal -----------------------------------------------------
    #: among grasps whose way in keeps too little room, one the whole-body IK reaches only with
    #: a torso joint nearer its limit than this comes after the others, rad (the torso leaning
    #: as far as it goes, the stretched arm yielded to what the hand met and closed on a lid
    #: tilted 14°: :mod:`~oacdsl.runtime.motion.approach`)
    torso_margin_rad: float = 0.05
    #: longest time for the fingers to close on an object, s
    close_s: float = 0.6
    #: longest time for the fingers to close again on an object being turned, s
    reclose_s: float = 0.7
    #: time for the fingers to open, s
    open_s: float = 0.4
    #: a hand whose boxes would reach this much lower, opened, than they do now opens only its
    #: fingers and keeps its thumb, m (the thumb of a pinch on a plate's rim swung down into a rack)
    open_drop_m: float = 0.02
    #: shares of the way to the open hand a hand letting go opens when opening fully would bring
    #: it nearer than ``arm_room_m`` to a neighbour (largest first; it opens fully once withdrawn)
    release_open_share: tuple[float, ...] = (0.75, 0.5, 0.25, 0.0)
    #: how far an open hand backs off along its grasp's approach, m, and rises meanwhile, m
    withdraw_back_m: float = 0.12
    withdraw_rise_m: float = 0.03
    #: how far it then rises, m
    withdraw_up_m: float = 0.08
    #: times of the two parts of a withdrawal, s
    withdraw_back_s: float = 0.8
    withdraw_up_s: float = 0.6

    # --- retreat to the home pose ----------------------------------------------------------
    #: how far an empty hand first rises before it goes home, m
    retreat_rise_m: float = 0.05
    #: share of the retreat's time spent rising
    retreat_rise_share: float = 0.25
    #: how far from where it was sent a hand (or what it carries) may end, m
    arrive_tolerance_m: float = 0.05

    # --- hold still ------------------------------------------------------------------------
    hold_s: float = 0.5
    #: how far a held object may drift while held still, m
    still_m: float = 0.02

    # --- repeated paths (circles) ----------------------------------------------------------
    #: shortest time of one waypoint of a repeated path, s: two control ticks. In one tick a
    #: waypoint is a jump the arms do not follow (KIT Mix at double speed: 0.44 s circles cut
    #: into 16 waypoints of one tick each ran at 0.32 s, and the servers circled 2 mm, not 22)
    waypoint_min_s: float = 0.04

    # --- slide along a surface -------------------------------------------------------------
    #: mean speed of a slide (a stroke of a tool on a surface), m/s, and its shortest time, s
    slide_speed_m_s: float = 0.06 / 0.7
    slide_min_s: float = 0.7
    #: a slide that loses its contact is lowered at this speed, m/s, at most this far, m
    seek_speed_m_s: float = 0.02
    seek_max_m: float = 0.03


#: The defaults every primitive uses unless told otherwise.
TUNING = Tuning()
