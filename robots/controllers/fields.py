"""Dynamic neural fields: cooperative EKMs (thesis ch. 5, Fig. 1.4b, Fig. 5.1).

Every map here shares the trained indirect map's input weights w_i and control matrices M_i — nothing
is retrained (ch. 5.3: "each neuron i in the obstacle avoidance EKMs has the same input weight vector
w_i as the neuron i in the target reaching EKMs"). One tick of ``form=thesis``:

1. target localisation EKM: winner s for the checkpoint u_p (Eq. 5.1 = Eq. 4.2–4.4);
2. target field G_a(w_s, w_i) = exp(−D_a / σ_a²), D_a = γ_α Δα² + γ_d Δd² with γ_d ≫ γ_α (Eq. 5.3):
   distance-sensitive and angle-insensitive, so the neurons at the target's distance in other
   directions stay active — where the robot can go round an obstacle;
3. one obstacle localisation EKM per sensor: winner s_j for u_j = (φ_j, r_j) of every sensor that sees
   something; obstacle field b_i = Σ_j G_b(w_sj, w_i) (Eq. 5.6), a Gaussian stretched along the
   obstacle's direction by δ_d so that the neurons *beyond* the obstacle are inhibited too;
4. activity a_i = G_a − b_i (Eq. 5.2), winner k = argmax a_i (Eq. 5.4);
5. c = M_k u_p if it is within ±c* and k = s, else M_k w_k (Eq. 5.5, :func:`ekm.indirect.command`).

With no obstacle sensed b = 0, k = s and the command is the indirect map's (Eq. 4.5).

Where the equations are silent, this module chooses (and says why):

- **Units.** D_a and D_b are taken in the map's own units, ũ = (α/π, d/d_scale) with angle differences
  wrapped (:class:`ekm.config.EKMConfig`), the units of the winner search (Eq. 4.3), so the fields' γ's
  and δ's compare with the map's. δ_d's own argument — its exponent 0.01 and its τ — is in metres, the
  unit in which the thesis gives τ (0.5 cm, ch. 6.2.2).
- **δ_d.** Beyond the obstacle (d_i ≥ d_s), 1 − (d_i − d_s)^0.01 with the difference in metres is
  0.03–0.09 for 1 mm … 5 cm: the Gaussian hardly decays along the obstacle's direction (the "stretch"),
  and it is 1 at the obstacle itself. Before it, 1 + ((d_s − d_i)/τ)⁴ makes it vanish within about 2τ,
  so the way up to the obstacle stays open.
- **The two τ's.** The thesis names the sensor resolution τ = 0.5 cm (ch. 6.2.2) and δ_d's τ (ch. 5.3)
  alike; both are 0.5 cm here, δ_d's being its own parameter (``tau``).
- **Where an obstacle is.** A reading r_j is the distance from the body surface (ch. 6.2.2); u_j =
  (φ_j, r_j) places the obstacle where the robot's *centre* would be when its body touched it — the
  obstacle grown by the body radius, as the planner pads obstacles (ch. 3.2.2), in the space of centre
  displacements that the w_i encode.

**``form=extended``** (the default) is a departure, measured side by side with the thesis's form in
``docs/reproduce/architectures.md``. As written, the fields keep nothing between ticks: each tick the robot takes the
free direction nearest the target, dithers where that direction flips from side to side (mid-wall, the
mouth of a U), and forgets a U's bottom once it is out of the sensors' 0.2 m. The extension keeps the
fields' equations and adds four things, each with its reason:

1. **remembered obstacles** (:mod:`robots.controllers.memory`): the IR hits are kept in the world frame
   and fed to the obstacle field every tick from wherever the robot is — the obstacle fields
   "remembered across steps and carried with the robot's odometry"; only those nearer than the target
   count (an obstacle beyond the target cannot block the way to it); a ray forgets a remembered point only when
   it passes within ``see_through`` (5 mm, the points' radius) of it, not within the 1 cm of ``merge`` that forgot
   a wall's end beside the ray that just missed it, and the robot drove into the end (issue 35, ``niches:0``) —
   but a point last sensed on a declared mover within ``merge`` still, so that the trail a mover leaves in the
   memory clears as the rays sweep it (measured in docs/reproduce/every-kind.md);
2. **obstacles where they are** (:func:`body_field`): the field of a remembered point is centred on
   the point itself, not on its localisation winner — the lattice's ~24° rows would otherwise shift a
   doorway's edges into the doorway — and its angular width is the angle the robot's body subtends at
   the point's distance (Eq. 5.6's δ_α scaled by distance): a near obstacle blocks a wide fan of
   directions, a far one a narrow one, whereas a fixed δ_α lets a wall seen from afar close a doorway;
   the clearance the width adds to the body follows the sensed gap (:func:`gap_clearance`, ``gap_share``,
   issue 35): a quarter of the room a passage leaves the body, at most 1 cm, so that a passage barely
   wider than the robot (a niche 7.5 cm wide) stays open; in such a passage the commitment to a side (3.) starts
   only when the robot's body itself would touch (``narrow_start``), since off the passage's centre line the body
   and its clearance never see the way open and the robot went round the room instead of in;
3. **commitment to a side** (:func:`committed_winner`, ``commit``): while a remembered obstacle lies
   between the robot and the target, the robot keeps to the side it first turned to and takes the
   first open direction turning from the target's direction that way — the target field measured one
   way round only — so it goes round a wall or out of a U instead of dithering;
4. **declared movers** (issue 32): the robot steps straight ahead or back when a mover the world declares would
   hit it standing (:mod:`~robots.controllers.escape`, ``escape_s``, shared with Samba); and a mover crossing the
   robot's line of sight (:func:`crossing`) is an obstacle where it is and where its velocity takes it over
   ``mover_ahead_s`` seconds (:func:`mover_inputs`; its IR returns bound to it, not lingering as still points), one
   that closes directions but never starts the commitment to a side — it passes, a wall does not. A mover coming
   or going along the line of sight keeps its bearing and does not pass: the IR sees it as it sees a wall, and the
   robot goes round it (a mover shuttling along the corridor the route needs). The robot reaches straight for an
   open target unless a mover whose track passes it is near (:func:`movers_near`, ``mover_track``): one passing
   beside it in a lane of its own does not stop it. Measured on the tuning seeds in ``docs/reproduce/every-kind.md``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cache, partial
from typing import NamedTuple

import jax
import jax.numpy as jnp

from ekm import indirect
from ekm.config import EKMConfig
from ekm.angles import wrap, wrap_near
from ekm.kohonen import relative, winner
from robots.controllers import escape as esc
from robots.controllers import memory as mem
from robots.controllers.base import Controller, Observation, sensor_angles
from robots.params import KHEPERA, RobotParams

FORMS = ("extended", "thesis")  # the default first

#: The chart of the map the fields use when no map is given: the signed chart's neurons reach 0.16 m
#: behind the robot as well as ahead (README, Fig. 6.2), so every direction has a full step to offer.
DEFAULT_CHART = "signed"


@dataclass(frozen=True)
class FieldParams:
    """Parameters of the neural fields; the defaults are the best documented variant (``docs/reproduce/architectures.md``)."""

    sensors: str = field(default="long", metadata={"help": "IR ring: long (12 around, 17.5 cm; ch. 6.2.2) or short",
                                                   "choices": ("short", "long")})
    form: str = field(default="extended", metadata={
        "help": "extended: remembered obstacles and commitment to a side (a departure); thesis: ch. 5 as written",
        "choices": FORMS})
    gamma_alpha: float = field(default=0.1, metadata={"help": "γ_α of the target field (Eq. 5.3), map units"})
    gamma_d: float = field(default=1.0, metadata={"help": "γ_d of the target field (Eq. 5.3), map units"})
    sigma_a: float = field(default=0.3, metadata={"help": "σ_a of the target field (Eq. 5.3)"})
    delta_alpha: float = field(default=1.0, metadata={"help": "δ_α of the obstacle field (Eq. 5.6), map units; "
                                                              "form=thesis"})
    sigma_b: float = field(default=0.15, metadata={"help": "σ_b of the obstacle field (Eq. 5.6)"})
    tau: float = field(default=0.005, metadata={"help": "τ of δ_d (Eq. 5.6), m"})
    memory_s: float = mem.option("memory_s", 60.0, "form=extended")
    memory_points: int = mem.option("memory_points", 256, "form=extended")
    merge: float = mem.option("merge", 0.01, "form=extended")
    see_through: float = mem.option("see_through", 0.005, "form=extended", "the points' radius, merge / 2; it was "
                                    "merge, which forgot a wall's end beside a ray that missed it")
    clearance: float = field(default=0.01, metadata={"help": "form=extended: m kept between the body and a "
                                                             "remembered obstacle"})
    commit: bool = field(default=True, metadata={"help": "form=extended: keep to one side of an obstacle until "
                                                         "the way to the target is open"})
    direct: bool = field(default=True, metadata={"help": "form=extended: while the way to the target is open and no "
                                                         "mover is near, reach for it (the target winner s, Eq. 4.5)"})
    near: float = field(default=0.08, metadata={"help": "form=extended: m a direction must be open for the body alone "
                                                         "when none is open, with the clearance, as far as the target"})
    mover_near: float = field(default=0.15, metadata={"help": "form=extended, direct: m from the body within which "
                                                              "a declared mover makes the fields weigh every obstacle"})
    mover_track: bool = field(default=True, metadata={
        "help": "form=extended, direct: a declared mover within mover_near stops the robot reaching straight for the "
                "target only if its track (the line along its velocity) passes within the clearance of the robot "
                "standing; false: any mover within mover_near"})
    guard_s: float = field(default=0.5, metadata={"help": "form=extended: s of travel to the nearest remembered "
                                                          "obstacle in the way of the wheels' motion (0: no guard)"})
    guard_clearance: float = field(default=0.01, metadata={"help": "form=extended: m beside the body within which a "
                                                                  "remembered obstacle is in the way of the wheels"})
    mover_ahead_s: float = field(default=1.0, metadata={
        "help": "form=extended: s ahead along its velocity up to which a declared mover crossing the line of sight "
                "counts as an obstacle where it will be, as well as where it is (0: movers only as the IR sees them)"})
    escape_s: float = field(default=1.5, metadata={
        "help": "form=extended: a declared mover that would hit the robot standing where it is within this many s: it "
                "drives straight ahead or back out of the mover's way (0: never), s"})
    gap_share: float = field(default=0.25, metadata={
        "help": "form=extended: the clearance beside a remembered obstacle is at most this share of the room the "
                "sensed gap across the way to the target leaves the body (0: fixed)"})

    narrow_start: bool = field(default=True, metadata={
        "help": "form=extended, commit: in a passage narrower than the body and twice the clearance (gap_share), the "
                "commitment to a side starts only when a still obstacle blocks the way to the target for the body "
                "itself, not for the body and its clearance"})
    guard_room: bool = field(default=True, metadata={
        "help": "form=extended: the guard's clearance is at most the room the robot has now (its nearest remembered "
                "still obstacle) less guard_margin, so that a wall it already runs beside does not stop it"})
    guard_margin: float = field(default=0.003, metadata={"help": "form=extended, guard_room: m taken off the room the "
                                                                 "robot has now for the guard's clearance"})
    guard_reads: bool = field(default=True, metadata={
        "help": "form=extended: the guard counts this tick's IR returns as well as the remembered points (a return "
                "within merge of a remembered point refreshes it where it was, up to merge farther than the wall)"})

    def __post_init__(self):
        for name in ("gamma_alpha", "gamma_d", "sigma_a", "delta_alpha", "sigma_b", "tau", "memory_s", "merge",
                     "see_through"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)}")
        if min(self.clearance, self.guard_s, self.mover_near, self.gap_share, self.escape_s, self.mover_ahead_s,
               self.guard_margin) < 0:
            raise ValueError("clearance, guard_s, mover_near, gap_share, escape_s, mover_ahead_s and guard_margin must "
                             f"be >= 0, got {self.clearance}, {self.guard_s}, {self.mover_near}, {self.gap_share}, "
                             f"{self.escape_s}, {self.mover_ahead_s}, {self.guard_margin}")
        if self.memory_points < 1:
            raise ValueError(f"memory_points must be >= 1, got {self.memory_points}")


# ------------------------------------------------------------------------------------------ the fields

def target_field(w, s, p: FieldParams, cfg: EKMConfig):
    """G_a(w_s, w_i) ``(N²,)`` of Eq. 5.3 around the target localisation winner ``s``."""
    diff = relative(w[s], w, cfg)
    return jnp.exp(-(p.gamma_alpha * diff[:, 0] ** 2 + p.gamma_d * diff[:, 1] ** 2) / p.sigma_a**2)


def delta_d(d_s, d_i, tau: float):
    """δ_d(d_s, d_i) of Eq. 5.6 (distances in m): 1 − (d_i − d_s)^0.01 beyond the obstacle, 1 + ((d_s − d_i)/τ)⁴
    before it (and 1 at it)."""
    gap = d_i - d_s
    stretch = 1.0 - jnp.exp(0.01 * jnp.log(jnp.maximum(gap, 1e-30)))  # gap ** 0.01, without pow's checks
    before = jnp.square(jnp.square(gap / tau))
    return jnp.where(gap > 0, stretch, 1.0 + before)


def obstacle_field(w, winners, seen, p: FieldParams, cfg: EKMConfig):
    """b_i ``(N²,)`` of Eq. 5.6: the sum of G_b(w_s, w_i) over the obstacle winners ``winners`` ``(h,)`` whose
    sensor saw something (``seen`` ``(h,)``; G_b = 0 otherwise)."""
    ws = w[winners]  # (h, 2)
    diff = relative(ws[:, None, :], w[None, :, :], cfg)  # (h, N², 2), w_s - w_i in map units
    dd = delta_d(ws[:, None, 1], w[None, :, 1], p.tau)
    g = jnp.exp(-(p.delta_alpha * diff[..., 0] ** 2 + dd * diff[..., 1] ** 2) / p.sigma_b**2)
    return jnp.sum(jnp.where(seen[:, None], g, 0.0), axis=0)


def body_field(w, u_obs, valid, radius: float, p: FieldParams, cfg: EKMConfig, clearance=None):
    """b_i ``(N²,)`` of obstacles placed where they are (``form=extended``): Eq. 5.6's stretched Gaussian
    centred on each obstacle's own (α_j, d_j), with δ_α scaled so that its angular half-width (where
    G_b = e⁻¹) is the angle the robot's body subtends there (:func:`memory.cone_half_width`), grown by
    ``clearance`` (m, one per obstacle ``(h,)``; default ``p.clearance``)."""
    clearance = p.clearance if clearance is None else clearance
    half = mem.cone_half_width(u_obs[:, 1], radius=radius, clearance=clearance)  # rad
    d_alpha = wrap_near(u_obs[:, None, 0] - w[None, :, 0])  # (h, N²)
    d_d = (u_obs[:, None, 1] - w[None, :, 1]) / cfg.d_scale  # map units
    dd = delta_d(u_obs[:, None, 1], w[None, :, 1], p.tau)
    g = jnp.exp(-jnp.square(d_alpha / half[:, None]) - dd * jnp.square(d_d) / p.sigma_b**2)
    return jnp.sum(jnp.where(valid[:, None], g, 0.0), axis=0)


def gap_clearance(u_obs, valid, target_alpha, radius: float, p: FieldParams):
    """The clearance (m) each remembered obstacle ``u_obs`` ``(h, 2)`` (where ``valid``) keeps beside the body
    (``form=extended``, an extension of Eq. 5.6's width, issue 35): ``min(p.clearance, gap_share × (g_j − 2R))``,
    g_j the gap (m, surface to surface) from obstacle j to the nearest obstacle on the other side of the target's
    direction ``target_alpha`` — the width of the passage the robot takes between them. A fixed clearance of 1 cm
    leaves a robot 5 cm wide 2.5 mm of play in a 7.5 cm passage: every direction into it is closed unless the
    robot is on its centre line, and the fields push the robot off a narrow niche's mouth. Following the gap, the
    inhibition narrows where the passage does, and is the thesis's (a body-wide cone) where it has room."""
    if p.gap_share <= 0:
        return jnp.full(u_obs.shape[:1], p.clearance)
    r = u_obs[:, 1] + radius  # from the robot's centre
    xy = jnp.stack([r * jnp.cos(u_obs[:, 0]), r * jnp.sin(u_obs[:, 0])], axis=-1)
    side = wrap(u_obs[:, 0] - target_alpha) >= 0
    across = valid[:, None] & valid[None, :] & (side[:, None] != side[None, :])
    gap = jnp.min(jnp.where(across, jnp.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1)), jnp.inf), axis=1)
    return jnp.clip(p.gap_share * (gap - 2 * radius), 0.0, p.clearance)


#: How many places along its path ahead (now, and evenly up to ``mover_ahead_s``) a declared mover is put.
MOVER_PLACES = 3


def crossing(markers, pose):
    """Which declared movers ``markers`` ``(k, 5)`` (x, y, vx, vy, radius; world frame) cross the robot's line of
    sight ``(k,)``: their velocity's part across the line from the robot at ``pose`` to them is larger than its part
    along it. Why: the places ahead of a crossing mover sweep across the directions the robot could take, and it
    passes out of the way; one coming along the line (or going away, or standing) keeps its bearing and does not
    pass — as a wall, the robot must go round it (a mover shuttling along the corridor the route needs)."""
    markers = jnp.asarray(markers, jnp.float32).reshape(-1, 5)
    los = markers[:, :2] - jnp.asarray(pose[:2], jnp.float32)
    along = jnp.abs(los[:, 0] * markers[:, 2] + los[:, 1] * markers[:, 3])
    across = jnp.abs(los[:, 0] * markers[:, 3] - los[:, 1] * markers[:, 2])
    return across > along


def mover_inputs(markers, pose, radius: float, ahead_s: float):
    """Obstacle inputs u = (α, d) ``(k · MOVER_PLACES, 2)`` of the declared movers ``markers`` ``(k, 5)`` (x, y, vx,
    vy, radius; world frame) where each is now and where it will be, at its velocity, evenly up to ``ahead_s``
    seconds ahead — d from the robot's surface to the mover's — and each one's radius ``(k · MOVER_PLACES,)``,
    which :func:`fields` adds to the clearance so that the cone it blocks is the mover's disc's
    (``form=extended``, an extension: the thesis's fields see a mover only by IR, and only where it was)."""
    markers = jnp.asarray(markers, jnp.float32).reshape(-1, 5)
    when = jnp.linspace(0.0, ahead_s, MOVER_PLACES)
    at = markers[:, None, :2] + when[None, :, None] * markers[:, None, 2:4]  # (k, places, 2)
    dx, dy = at[..., 0] - pose[0], at[..., 1] - pose[1]
    r = jnp.broadcast_to(markers[:, 4:5], dx.shape)
    alpha = wrap(jnp.arctan2(dy, dx) - pose[2])
    d = jnp.maximum(jnp.hypot(dx, dy) - radius - r, 0.0)
    return jnp.stack([alpha, d], axis=-1).reshape(-1, 2), r.reshape(-1)


def obstacle_inputs(readings, angles):
    """u_j = (φ_j, r_j) ``(h, 2)`` of each sensor and whether it sees anything ``(h,)``."""
    seen = jnp.isfinite(readings)
    return jnp.stack([angles, jnp.where(seen, readings, 0.0)], axis=-1), seen


class Tick(NamedTuple):
    """The fields of one tick (for the controller and for plots): target winner ``s``, G_a, b and
    a = G_a − b ``(N²,)``, and the obstacle inputs ``u_obs`` ``(h, 2)`` that count (``valid``)."""

    s: jax.Array
    g_a: jax.Array
    b: jax.Array
    a: jax.Array
    u_obs: jax.Array
    valid: jax.Array


class Blocked(NamedTuple):
    """Which of the neurons' directions and (last) the target's are blocked ``(N² + 1,)`` each, for
    :func:`committed_winner` (:func:`memory.blocked_along`; none for ``form=thesis``): ``way`` by anything the body
    would touch before reaching the target, except that the target's own direction counts still obstacles only (a
    mover passes: the robot does not commit to going round it); ``near`` for the body alone as far as ``near``;
    ``mover`` by a mover; and ``starts`` ``()``, whether the target's direction is blocked enough to start the
    commitment to a side (:func:`commitment_starts`)."""

    way: jax.Array
    near: jax.Array
    mover: jax.Array
    starts: jax.Array


class FieldState(NamedTuple):
    """What the fields carry between ticks: the remembered obstacles (``form=extended``), the side the robot
    keeps to (+1 left, −1 right, 0 none) and the last winners s and k (for plots)."""

    memory: mem.Memory
    side: jax.Array
    s: jax.Array
    k: jax.Array


@cache
def init(p: FieldParams) -> FieldState:
    return FieldState(mem.empty(p.memory_points if p.form == "extended" else 1), jnp.asarray(0.0, jnp.float32),
                      jnp.asarray(0, jnp.int32), jnp.asarray(0, jnp.int32))


def fields(state: FieldState, ekm, obs: Observation, angles, p: FieldParams, cfg: EKMConfig, *, radius: float,
           range_m: float) -> tuple[FieldState, Tick, Blocked]:
    """Eq. 5.1–5.3 and 5.6 for one tick. ``form=extended`` first adds the tick's readings to the remembered
    obstacles (those on a declared mover left out while ``mover_ahead_s`` places the movers, :func:`mover_inputs`),
    then builds b from those nearer than the target (:func:`body_field`). Also returns, for
    :func:`committed_winner`, the directions that are blocked (:class:`Blocked`)."""
    s = winner(ekm.w, obs.target, cfg)
    g_a = target_field(ekm.w, s, p, cfg)
    if p.form == "extended":
        if p.mover_ahead_s > 0:  # crossing movers by their places ahead; the others by the IR, as still obstacles
            markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
            placed = crossing(markers, obs.pose)
            ir = mem.off_movers(obs.pose, obs.ir, angles, markers.at[:, 4].set(jnp.where(placed, markers[:, 4], -1.0)),
                                radius=radius)
        else:
            ir = obs.ir
        memory = mem.update(state.memory, obs.pose, ir, angles, obs.t, radius=radius, range_m=range_m,
                            merge=p.merge, forget_after=p.memory_s, through=p.see_through,
                            markers=obs.markers)
        state = state._replace(memory=memory)
        u_obs, valid = mem.egocentric(memory, obs.pose, radius=radius)
        grown = jnp.zeros_like(u_obs[:, :1])  # m each obstacle adds to the clearance: 0 for a point
        if p.mover_ahead_s > 0:
            u_mov, r_mov = mover_inputs(markers, obs.pose, radius, p.mover_ahead_s)
            u_obs, grown = jnp.concatenate([u_obs, u_mov]), jnp.concatenate([grown, r_mov[:, None]])
            valid = jnp.concatenate([valid, jnp.repeat(placed, MOVER_PLACES)])
        valid = valid & (u_obs[:, 1] < obs.target[1])
        directions = jnp.append(ekm.w[:, 0], obs.target[0])

        def per_neuron(ug, v):  # on the points that count only (most slots are empty or beyond the target)
            u, r = ug[:, :2], ug[:, 2]
            clear = jnp.where(r > 0, p.clearance, gap_clearance(u, v & (r == 0), obs.target[0], radius, p)) + r
            blocked = mem.blocked_along(directions, obs.target[1], u, v, radius=radius, clearance=clear)
            # the way to the target counts as blocked (the commitment to a side) for still obstacles only: a mover
            # passes, and going round it as round a wall took the robot round the room (issue 32)
            way = mem.blocked_along(directions[-1:], obs.target[1], u, v & (r == 0), radius=radius,
                                    clearance=clear)[0]
            starts = commitment_starts(obs.target, u, v & (r == 0), clear, p, radius=radius) if p.narrow_start else way
            return body_field(ekm.w, u, v, radius, p, cfg, clear), Blocked(
                blocked.at[-1].set(way),
                mem.blocked_along(directions, jnp.minimum(obs.target[1], p.near), u, v, radius=radius, clearance=r),
                mem.blocked_along(directions, obs.target[1], u, v & (r > 0), radius=radius, clearance=clear), starts)

        b, blocked = mem.over_packed(per_neuron, jnp.concatenate([u_obs, grown], axis=1), valid)
    else:
        u_obs, valid = obstacle_inputs(obs.ir, angles)
        winners = jax.vmap(lambda u: winner(ekm.w, u, cfg))(u_obs)
        b = obstacle_field(ekm.w, winners, valid, p, cfg)
        none = jnp.zeros(ekm.w.shape[0] + 1, bool)
        blocked = Blocked(none, none, none, jnp.asarray(False))
    return state, Tick(s, g_a, b, g_a - b, u_obs, valid), blocked


def commitment_starts(target, u_obs, still, clear, p: FieldParams, *, radius: float):
    """Whether the still obstacles ``u_obs`` ``(K, 2)`` (where ``still``), each with its clearance ``clear`` ``(K,)``
    (m, :func:`gap_clearance`), block the straight way to the ``target`` (α, d) enough to start the commitment to a
    side: for the body and its clearance, or — with ``narrow_start``, beside an obstacle whose clearance the passage
    narrowed below ``p.clearance`` — for the body itself. Why: off a niche's centre line by a few millimetres the
    body and its clearance never see the way in open, and the committed robot went round the room instead of in
    (issue 35, ``niches``); the commitment, once started, still lasts while the way is blocked with the clearance."""
    if p.narrow_start:
        clear = jnp.where(clear < p.clearance, 0.0, clear)
    return mem.blocked_along(target[:1], target[1], u_obs, still, radius=radius, clearance=clear)[0]


def committed_winner(w, k, b, target, side, blocked, p: FieldParams, cfg: EKMConfig, direct=True, blocked_near=None,
                     starts=None):
    """The winner when the robot commits to one side of an obstacle (``form=extended``; see the module
    docstring). ``blocked`` ``(N² + 1,)``: which neurons' directions and (last) the target's a remembered
    obstacle blocks nearer than the target (:func:`memory.blocked_along`); ``starts``: whether the way is blocked
    enough to start a commitment (default: ``blocked[-1]``; with ``narrow_start``, in a narrow passage for the body
    itself). Returns ``(k, side)``.

    While a remembered obstacle lies between the robot and the target (the target's direction blocked),
    the robot keeps to the side the thesis's winner ``k`` lay on when that began (when ``starts``),
    and takes the first *open* direction met turning from the target's direction towards that side —
    open: no remembered obstacle the body would touch along it before the target's distance — as a robot
    going round an obstacle with it on the other hand. Among the neurons of that direction, the target field
    (Eq. 5.3, its angle measured one way round only) picks the one nearest the target's distance. When no direction
    is open the thesis's winner stands; when the way to the target is open again, the commitment ends.
    """
    way_blocked = blocked[-1]
    starts = way_blocked if starts is None else starts
    first_side = jnp.where(wrap(w[k, 0] - target[0]) >= 0, 1.0, -1.0)
    side = jnp.where(way_blocked, jnp.where(side == 0, jnp.where(starts, first_side, 0.0), side), 0.0)
    swept = jnp.mod(side * (w[:, 0] - target[0]), 2.0 * jnp.pi) / jnp.pi  # 0 … 2 half-turns, one way round
    dd = relative(w[winner(w, target, cfg)], w, cfg)[:, 1]
    g = jnp.exp(-(p.gamma_alpha * swept**2 + p.gamma_d * dd**2) / p.sigma_a**2)
    # Open, and going somewhere: a neuron whose displacement is a small fraction of the way to the target is
    # open in every direction and would stall the robot (the lattice's centre neurons, |d_i| of millimetres).
    going = jnp.abs(w[:, 1]) >= jnp.minimum(0.25 * target[1], 0.02)
    # Open as far as the target, or — where nothing is (a corridor hardly wider than the robot: every direction
    # passes within the clearance of a wall before the target) — for the body alone as far as ``near``.
    open_far = ~blocked[:-1] & going
    open_ = jnp.where(jnp.any(open_far), open_far, ~blocked_near & going)
    k_side = jnp.where(jnp.any(open_), jnp.argmax(jnp.where(open_, g - b, -jnp.inf)), k)
    k_open = jnp.where(direct, winner(w, target, cfg), k) if p.direct else k
    return jnp.where(side != 0, k_side, k_open), side


@partial(jax.jit, static_argnames=("cfg", "p", "radius", "range_m", "max_speed"))
def step(state: FieldState, obs: Observation, ekm, angles, *, cfg: EKMConfig, p: FieldParams, radius: float,
         range_m: float, max_speed: float = KHEPERA.max_wheel_speed):
    """One tick of the cooperative EKMs: winner k of a = G_a − b (Eq. 5.2, 5.4) and its command (Eq. 5.5)."""
    state, f, blocked = fields(state, ekm, obs, angles, p, cfg, radius=radius, range_m=range_m)
    k = jnp.argmax(f.a)
    if p.form == "extended" and p.commit:
        near = movers_near(obs, radius, p.mover_near, p.clearance if p.mover_track else None)
        k, side = committed_winner(ekm.w, k, f.b, obs.target, state.side, blocked.way, p, cfg,
                                   direct=~near & ~blocked.mover[-1], blocked_near=blocked.near[:-1],
                                   starts=blocked.starts)
        state = state._replace(side=side)
    u = jnp.where(k == f.s, obs.target, ekm.w[k])  # Eq. 5.5: M_k u_p only for k = s, else M_k w_k
    c = indirect.command(ekm, u, k, cfg)
    if p.form == "extended" and (p.guard_s > 0 or p.escape_s > 0):
        still = jnp.isfinite(state.memory.seen) & ~mem.near_movers(state.memory.points, obs.markers)
        if p.guard_s > 0:
            c = guard(c, *guard_inputs(state.memory, still, obs, angles, radius, p), radius, p)
        if p.escape_s > 0:
            c = out_of_the_way(c, state.memory.points, still, obs, radius, max_speed, p)
    return state._replace(s=f.s.astype(jnp.int32), k=k.astype(jnp.int32)), c


def movers_near(obs: Observation, radius: float, gap: float, track: float | None = None):
    """Whether a declared mover (``obs.markers``: x, y, vx, vy, radius) is within ``gap`` (m, surface to surface) of
    the robot — and, with ``track`` (m), also comes within ``track`` of the robot standing where it is: a mover
    closing in by its track's nearest approach, ``|Δp × v| / |v| − r_mover − radius`` (the straight line along its
    velocity), any other (going away, or standing) by where it is now. Why the track: a mover shuttling along the
    corridor the route needs is within 15 cm of the robot all the way up the lane it leaves free, and the fields,
    weighing every obstacle there, turned from the lane and dithered at the corridor's mouth (issue 35,
    ``movers:6``)."""
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    dx, dy = markers[:, 0] - obs.pose[0], markers[:, 1] - obs.pose[1]
    vx, vy, r = markers[:, 2], markers[:, 3], markers[:, 4]
    d = jnp.hypot(dx, dy) - r - radius
    if track is None:
        return jnp.any(d < gap)
    closing = dx * vx + dy * vy < 0
    nearest = jnp.abs(dx * vy - dy * vx) / jnp.maximum(jnp.hypot(vx, vy), 1e-9) - r - radius
    return jnp.any((d < gap) & (jnp.where(closing, nearest, d) < track))


def guard_inputs(memory: mem.Memory, still, obs: Observation, angles, radius: float, p: FieldParams):
    """What the guard counts: the remembered points that are ``still`` ``(K,)`` as (α, d) ``(K, 2)`` and, with
    ``guard_reads``, this tick's IR returns ``(m, 2)`` after them (those on a declared mover left to its marker).
    Why the returns: a return within ``merge`` of a remembered point refreshes it where it was, so the memory can
    hold a wall up to ``merge`` farther than it is, and the robot backing past a corner hit it (issue 35; traced in
    ``docs/reproduce/every-kind.md``)."""
    u_obs = mem.egocentric(memory, obs.pose, radius=radius)[0]
    if not p.guard_reads:
        return u_obs, still
    markers = jnp.asarray(obs.markers, jnp.float32).reshape(-1, 5)
    u_ir, seen = obstacle_inputs(mem.off_movers(obs.pose, obs.ir, angles, markers, radius=radius), angles)
    return jnp.concatenate([u_obs, u_ir]), jnp.concatenate([still, seen])


def guard(c, u_obs, valid, radius: float, p: FieldParams):
    """The wheel command ``c`` ``(2,)`` with its forward (or backward) speed limited so that the robot needs at
    least ``guard_s`` to reach the nearest remembered obstacle in the body-wide cone straight ahead (behind,
    when it reverses); its turn rate is kept. The fields choose a *displacement*, but the wheels reach it
    along an arc that leaves along the current heading: this keeps that first stretch clear. With ``guard_room``
    the body is grown by ``guard_clearance`` or, if less, the room the robot has now less ``guard_margin``: a
    robot already nearer than ``guard_clearance`` to a wall beside it (in a niche hardly wider than itself) would
    otherwise find that wall in its way at every heading but the wall's own, and stand (issue 35)."""
    v, turn = 0.5 * (c[0] + c[1]), 0.5 * (c[1] - c[0])
    heading = jnp.where(v >= 0, 0.0, jnp.pi)
    clear = p.guard_clearance
    if p.guard_room:  # no more than the room the robot has now: a wall alongside, already nearer, does not stop it
        clear = jnp.clip(jnp.min(jnp.where(valid, u_obs[:, 1], jnp.inf)) - p.guard_margin, 0.0, clear)
    half = mem.cone_half_width(u_obs[:, 1], radius=radius, clearance=clear)
    ahead = valid & (jnp.abs(wrap_near(heading - u_obs[:, 0])) < half)
    free = jnp.min(jnp.where(ahead, u_obs[:, 1], jnp.inf))
    limit = jnp.maximum(free - 0.5 * p.clearance, 0.0) / p.guard_s
    slowed = jnp.sign(v) * limit
    return jnp.where(jnp.abs(v) > limit, jnp.stack([slowed - turn, slowed + turn]), c)


def out_of_the_way(c, points, still, obs: Observation, radius: float, max_speed: float, p: FieldParams):
    """The wheel command ``c`` ``(2,)``, or — when a declared mover would hit the robot standing within ``escape_s``
    — the straight motion ahead or back that puts the first contact off the longest (:mod:`~robots.controllers.
    escape`, shared with Samba and command fusion; the remembered ``points`` ``(K, 2)`` that are ``still`` count along
    the ray), the body grown by the clearance. Why: the fields choose a displacement the wheels reach along an arc
    that starts with a turn, and a robot turning in a mover's path is hit (measured in
    ``docs/reproduce/every-kind.md``)."""
    return esc.out_of_the_way(c, points, still, obs.markers, obs.pose, radius + p.clearance, max_speed, p.escape_s,
                              ESCAPE_SPEEDS)


#: Speeds (evenly up to the robot's top speed) among which :func:`out_of_the_way` picks, as Samba's grid has.
ESCAPE_SPEEDS = 8


def build(params: FieldParams, ekm, cfg: EKMConfig, robot: RobotParams = KHEPERA, spec: str = "fields") -> Controller:
    """Neural fields over the indirect map ``ekm`` (one trial) on ``robot``."""
    sensors = robot.short_range if params.sensors == "short" else robot.long_range
    angles = jnp.asarray(sensor_angles(sensors))
    run = partial(step, ekm=ekm, angles=angles, cfg=cfg, p=params, radius=robot.radius, range_m=sensors.range_m,
                  max_speed=robot.max_wheel_speed)
    return Controller(name="fields", spec=spec, sensors=sensors, init=partial(init, params), step=run, params=params,
                      robot=robot)
