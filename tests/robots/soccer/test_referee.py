"""The referee (robots.soccer.referee): a goal is the ball's centre crossing a goal line between the posts into
the goal, counted once per entry; rule "centre" asks for the ball back on the centre spot; rule "sahota" (his
§4.3) counts no goal until the side scored upon has cleared the ball from its half. Balls rolled on a pymunk
pitch (deterministic) and hand-made positions."""

import pytest

from ekm.errors import InputError
from robots.soccer.ball import BallParams, Pitch
from robots.soccer.field import Field
from robots.soccer.referee import Score, judge

F = Field()  # 1.2 m × 0.8 m; mouth y in [0.28, 0.52]; goals 0.06 m deep; half-way line x = 0.6


def referee_positions(positions, rule="centre", score=Score()):
    """Judge a walk through ``positions``; the final score and the scorer of each counted goal."""
    scorers = []
    for p, q in zip(positions[:-1], positions[1:]):
        score, scored, _ = judge(score, p, q, F, rule)
        if scored is not None:
            scorers.append(scored)
    return score, scorers


def play(pitch, score, rule, steps, kick=None):
    """Optionally kick, then step the pitch ``steps`` times, judging each step; the ball's x after each step."""
    if kick is not None:
        pitch.kick(kick)
    xs, scorers = [], []
    prev = pitch.ball_position
    for _ in range(steps):
        pitch.step(0.016)
        q = pitch.ball_position
        score, scored, _ = judge(score, prev, q, pitch.field, rule)
        if scored is not None:
            scorers.append(scored)
        prev = q
        xs.append(q[0])
    return score, scorers, xs


# ------------------------------------------------------------------------------------ balls on a pitch

@pytest.mark.parametrize("defender, start, kick", [(0, (0.3, 0.4), (-0.3, 0.0)), (1, (0.9, 0.4), (0.3, 0.0))])
def test_a_ball_rolled_into_a_goal_is_one_goal_though_it_bounces_back_out_across_the_line(defender, start, kick):
    pitch = Pitch(Field(), BallParams(restitution=0.7, rolling_friction=0.0))
    pitch.place(*start)
    # 0.3 m to the line at 0.3 m/s: in after 1 s (63 steps), off the back of the goal (centre 0.04 m behind the
    # line), out again at 0.21 m/s about 0.4 s later; 150 steps (2.4 s) leave it 0.2 m back in the field
    score, scorers, xs = play(pitch, Score(), "centre", 150, kick)
    behind = [abs(x - F.goal_x(defender)) for x in xs if (x <= 0.0 if defender == 0 else x >= 1.2)]
    assert max(behind) == pytest.approx(0.04, abs=0.005)  # it reached the back of the goal: 0.06 - 0.02
    assert abs(xs[-1] - F.goal_x(defender)) > 0.1  # and came back out across the line
    assert scorers == [1 - defender]  # one goal, for the attacking side
    assert score.goals == ((0, 1) if defender == 0 else (1, 0))
    assert score.in_goal is None  # out of the goal area again


def test_a_ball_rolled_at_the_end_wall_beside_the_mouth_scores_nothing():
    pitch = Pitch(Field(), BallParams(restitution=0.7, rolling_friction=0.0))
    pitch.place(0.3, 0.15)  # below the lower post at y = 0.28
    score, scorers, xs = play(pitch, Score(), "centre", 150, (-0.3, 0.0))
    assert min(xs) > 0.0 and scorers == [] and score.goals == (0, 0)


def test_under_sahotas_rule_a_second_goal_counts_only_after_the_half_is_cleared():
    pitch = Pitch(Field(), BallParams(restitution=0.7, rolling_friction=0.0))
    pitch.place(0.3, 0.4)
    # first goal: into side 0's goal after 63 steps (0.3 m at 0.3 m/s), off its back (0.04 m further, 8 steps),
    # out across the line 8 steps later at 0.21 m/s; after 110 steps it is 0.21 × 0.016 × 31 ~ 0.1 m out, past
    # the goal area (0.06 m in front of the line)
    score, scorers, xs = play(pitch, Score(), "sahota", 110, (-0.3, 0.0))
    assert scorers == [1] and score.goals == (0, 1) and score.locked == 0
    assert xs[-1] > 0.06 and score.in_goal is None
    # kicked straight back in, still in side 0's half: a goal, but it does not count
    score, scorers, xs = play(pitch, score, "sahota", 60, (-0.3, 0.0))
    assert min(xs) < 0.0  # it did go in
    assert scorers == [] and score.goals == (0, 1) and score.locked == 0
    # cleared: kicked at 0.5 m/s up the field, past the half-way line x = 0.6 within 80 steps (0.64 m)
    score, _, xs = play(pitch, score, "sahota", 80, (0.5, 0.0))
    assert max(xs) > 0.6 and score.locked is None
    # and back into side 0's goal from x ~ 0.73: 0.73 / 0.3 = 2.4 s (152 steps); this one counts
    score, scorers, _ = play(pitch, score, "sahota", 170, (-0.3, 0.0))
    assert scorers == [1] and score.goals == (0, 2) and score.locked == 0


# ------------------------------------------------------------------------------------ hand-made positions

def test_the_crossing_point_not_the_end_point_must_lie_between_the_posts():
    # p = (0.02, 0.25) -> q = (-0.02, 0.29): crosses x = 0 half-way, at y = 0.27 < 0.28 (beside the post),
    # though q's y is inside the mouth
    assert referee_positions([(0.02, 0.25), (-0.02, 0.29)])[1] == []
    # p = (0.02, 0.27) -> q = (-0.02, 0.31): crosses at y = 0.29, inside the mouth
    assert referee_positions([(0.02, 0.27), (-0.02, 0.31)])[1] == [1]
    # right goal: p = (1.19, 0.53) -> q = (1.21, 0.51): crosses x = 1.2 at y = 0.52, on the post: counts
    assert referee_positions([(1.19, 0.53), (1.21, 0.51)])[1] == [0]


def test_a_ball_that_only_reaches_the_line_has_not_crossed_it_from_behind():
    # arriving exactly on the line counts (x <= 0); leaving the goal outwards never does
    assert referee_positions([(0.01, 0.4), (0.0, 0.4)])[1] == [1]
    assert referee_positions([(-0.03, 0.4), (0.01, 0.4)])[1] == []


def test_rocking_back_and_forth_across_the_line_is_one_goal():
    rocking = [(0.05, 0.4)] + [(0.01, 0.4), (-0.01, 0.4)] * 5  # five entries, never out of the goal area
    score, scorers = referee_positions(rocking)
    assert scorers == [1] and score.goals == (0, 1)


def test_leaving_the_goal_area_and_coming_back_is_a_new_goal_under_rule_centre():
    # out to x = 0.1 > the goal area's 0.06 m in front of the line, then back in: two entries
    walk = [(0.05, 0.4), (-0.01, 0.4), (0.1, 0.4), (-0.01, 0.4)]
    assert referee_positions(walk, "centre")[1] == [1, 1]
    # out to x = 0.05 only: still in the goal area, one goal
    assert referee_positions([(0.05, 0.4), (-0.01, 0.4), (0.05, 0.4), (-0.01, 0.4)], "centre")[1] == [1]


def test_sahota_rule_on_hand_made_positions_and_the_half_way_line_itself():
    score = Score()
    walk = [(0.05, 0.4), (-0.01, 0.4), (0.3, 0.4), (-0.01, 0.4)]  # goal, out into side 0's half, in again
    score, scorers = referee_positions(walk, "sahota", score)
    assert scorers == [1] and score == Score(goals=(0, 1), locked=0, in_goal=0)
    # exactly on the half-way line x = 0.6 is not across it; x = 0.61 is
    score, _ = referee_positions([(-0.01, 0.4), (0.6, 0.4)], "sahota", score)
    assert score.locked == 0
    score, _ = referee_positions([(0.6, 0.4), (0.61, 0.4), (0.05, 0.4), (-0.01, 0.4)], "sahota", score)
    assert score.goals == (0, 2) and score.locked == 0
    # the same walk under "centre" counts every entry: 1 + 1 + 1 = 3 goals
    assert referee_positions(walk + [(0.61, 0.4), (0.05, 0.4), (-0.01, 0.4)], "centre")[0].goals == (0, 3)


def test_recentre_is_asked_for_after_a_counted_goal_under_rule_centre_only():
    p, q = (0.01, 0.4), (-0.01, 0.4)
    assert judge(Score(), p, q, F, "centre").recentre is True
    assert judge(Score(), p, q, F, "sahota").recentre is False
    assert judge(Score(), (0.3, 0.4), (0.31, 0.4), F, "centre").recentre is False  # no goal


def test_judge_is_pure():
    score = Score(goals=(2, 3), locked=None, in_goal=None)
    first = judge(score, (0.01, 0.4), (-0.01, 0.4), F, "sahota")
    assert judge(score, (0.01, 0.4), (-0.01, 0.4), F, "sahota") == first
    assert score == Score(goals=(2, 3))
    assert first.score.goals == (2, 4)  # side 1 scored on side 0's goal


def test_an_unknown_rule_is_refused_in_one_line():
    with pytest.raises(InputError) as err:
        judge(Score(), (0.3, 0.4), (0.31, 0.4), F, "fifa")
    assert "rule" in str(err.value) and "fifa" in str(err.value) and "\n" not in str(err.value)
