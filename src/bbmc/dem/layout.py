"""Column layout of the engine's flat arrays, and the integer codes of the joint laws.

The engine keeps its state in a few 2D float arrays, one row per block or per sub-contact, whose
columns are named here; numba treats these module constants as compile-time constants, so a kernel
reads ``blocks[i, VX]`` at the cost of a plain index. Everything is SI: m, rad, s, kg, N, Pa, Pa/m.
Plane strain: a block's mass and inertia, a contact's length, forces and energies are per metre of
thickness unless the scene sets another thickness.
"""

# --- blocks: float64 (n_blocks, BLOCK_COLUMNS) ---------------------------------------------------
X, Y, TH = 0, 1, 2  # centroid [m], rotation from the initial position [rad]
VX, VY, W = 3, 4, 5  # velocity [m/s] and angular velocity [rad/s] at the last half step
SIZE = 6  # sqrt(area): the block size against which interpenetration is judged [m]
FX, FY, FM = 7, 8, 9  # out-of-balance force [N] and moment [N m] of the current step
# (columns 0-9 are all a contact reads and writes of its two blocks: two cache lines, not four)
MASS, INERTIA = 10, 11  # true mass [kg] and polar moment of inertia about the centroid [kg m^2]
MX, MY, MW = 12, 13, 14  # inertial mass per degree of freedom (density scaling may raise it)
X0, Y0 = 15, 16  # initial centroid [m]
XR, YR, THR = 17, 18, 19  # position at the last contact search [m, rad]
RADIUS = 20  # largest distance from the centroid to a vertex [m]
VPX, VPY, VPW = 21, 22, 23  # prescribed velocity of the prescribed degrees of freedom
PVX, PVY, PW = 24, 25, 26  # velocity of the half step before (energies are read at full steps)
VSTART = 27  # step from which the prescribed velocity applies (before it, prescribed dofs are held)
BLOCK_COLUMNS = 28

# --- block degrees of freedom: int64 (n_blocks, 3), one code per x, y, rotation ---------------------
FREE, PRESCRIBED = 0, 1  # a fixed degree of freedom is one prescribed at zero velocity

# --- contacts: int64 (n_contacts, CONTACT_COLUMNS); each owns N_SUB consecutive sub-contact rows ----
EDGE_A, EDGE_B = 0, 1  # global edge indices, of block A (the lower index) and of block B
BLOCK_A, BLOCK_B = 2, 3
JOINT_TYPE = 4
CONTACT_COLUMNS = 5

# --- sub-contacts: float64 (n_contacts * n_sub, SUB_COLUMNS) ---------------------------------------
SN, TAU = 0, 1  # mean normal (compression > 0) and shear stress on block A over the closed part [Pa]
UN = 2  # closure at the last step (> 0 closed) [m]: the closed part's mean; an open share's largest
US = 3  # accumulated shear displacement of B on A [m]
KN, KS = 4, 5  # current normal and shear stiffness [Pa/m]
COH, TANPHI, TEN = 6, 7, 8  # cohesion [Pa], tan(friction angle) [1], tensile strength [Pa]
LENGTH = 9  # length of this sub-contact's share of the contact's overlap [m] (0: contact inactive)
SLIPPED = 10  # 0 intact; SLIPPED_IN_SHEAR once it has slipped, FAILED_IN_TENSION once its bond broke
SLIPPED_IN_SHEAR, FAILED_IN_TENSION = 1.0, 2.0
BECAME_JOINT = 2.0  # added to SLIPPED where a share of intact rock has become its joint (3, 4)
CX, CY = 11, 12  # position [m]
PATH = 13  # shear displacement path length while closed, sum of |d u_s| [m] (damage never heals)
DILATION = 14  # normal opening by dilation so far [m]; the law's closure is u_n + DILATION
CLOSED = 15  # fraction of the share that is closed (carries stress) [1]
SUB_COLUMNS = 16  # 128 bytes a row: every step reads and writes each row whole (the engine's main traffic)

# --- sub-contacts' law state: float64 (n_contacts * n_sub, LAW_STATE_COLUMNS), rows as `subs` -------
# read by the law updates and the mobilized law's dilation only, so a step of the other scenes does not
# move them through memory (written in the step only where a share slips or breaks)
LAW_SN, LAW_TAU = 0, 1  # the stresses the laws were last evaluated at (nan: evaluate at the next update)
LAW_PATH = 2  # PATH when the joint laws were last evaluated [m]
TAN_DILATION = 3  # tan of the mobilized dilation angle at the last law update [1]
LAW_STATE_COLUMNS = 4

# corners are rounded over this fraction of the smaller block's size: within it of each other, two
# corners in contact turn the normal gradually from one face's to the other's (`contact_frame`)
CORNER_ROUNDING = 0.01

# --- joint types: int64 (n_types, LAW_COLUMNS) and float64 (n_types, PARAMETERS) --------------------
STRENGTH_LAW, NORMAL_LAW, SHEAR_LAW, AFTER_SLIP = 0, 1, 2, 3
BREAKS_INTO = 4  # the joint type an intact-rock type (a bridge) becomes where it breaks; -1: none
LAW_COLUMNS = 5
STRENGTH_CONSTANT, STRENGTH_BARTON_BANDIS = 0, 1  # M-C c, phi given | tangent to the B-B envelope (eq 15)
STRENGTH_MOBILIZED = 2  # secant of the B-B strength mobilized at the sub-contact's shear path (Barton 1982)
NORMAL_CONSTANT, NORMAL_EQ8, NORMAL_BANDIS = 0, 1, 2  # K_n given | eqs 5-8 | Bandis et al. 1983's hyperbola
SHEAR_CONSTANT, SHEAR_BANDIS, SHEAR_CORRECTED, SHEAR_SIMPLIFIED, SHEAR_HYPERBOLIC = 0, 1, 2, 3, 4
AFTER_SLIP_ZERO, AFTER_SLIP_KEEP = (
    0,
    1,
)  # cohesion after slip: 0 (Itasca's Coulomb slip) | kept (ductile, default)

(
    P_KN,
    P_KS,
    P_COH,
    P_PHI,
    P_TEN,
    P_JRC,
    P_JCS,
    P_PHI_B,
    P_PHI_MAX,
    P_K_TANGENT,
    P_Q,
    P_LG_E,
    P_K_J,
    P_N_J,
    P_SIGMA_REF,
    P_TAU_P_SLOPE,
    P_TAU_P_INTERCEPT,
    P_TAU_ULT_SLOPE,
    P_TAU_ULT_INTERCEPT,
    P_A,
    P_B,
    P_D,
    P_STRESS_FLOOR,
    P_SHEAR_FLOOR,
    P_STRENGTH_DIVISOR,
    P_PEAK_DISPLACEMENT,
    P_DAMAGE,
    P_K_NI,
    P_V_M,
) = range(29)
PARAMETERS = 29
# mobilized B-B (STRENGTH_MOBILIZED): P_JRC, P_JCS are the scaled JRC_n, JCS_n, P_PHI_B holds phi_r,
# P_PEAK_DISPLACEMENT delta_peak [m], P_DAMAGE the dilation's M (0: Barton, Bandis & Bakhtar's M(sigma_n));
# NORMAL_BANDIS: P_K_NI [Pa/m] and P_V_M [m], the closure hyperbola's initial stiffness and maximum closure
# P_STRENGTH_DIVISOR: strength reduction (`bbmc fos`): a sub-contact's shear strength c + sigma_n tan(phi)
# and its tensile strength are divided by it; 1 for every scene that `bbmc run` runs

# --- support elements: int64 (n_elements, 2) the two blocks, and float64 (n_elements, SUPPORT_COLUMNS) --
# An element joins a point of block A to a point of block B: an anchor's head and end, or a grouted
# bolt's two sides of one joint it crosses (`bbmc.dem.support`). Forces are per metre run [N/m].
ANCHOR, GROUTED = 0.0, 1.0  # KIND
KIND = 0
AX, AY, BX, BY = 1, 2, 3, 4  # the two points in their blocks' frames (from the centroid, unrotated) [m]
DIR_X, DIR_Y = 5, 6  # grouted: the bolt's axis at the start [1]
PLANE_X, PLANE_Y = 7, 8  # the joint it crosses: its tangent in A's frame (passive reduction) [1]
K_AXIAL, K_SHEAR = 9, 10  # stiffness [N/m per m]
PRETENSION = 11  # anchor [N/m]
CAP_AXIAL, CAP_SHEAR = 12, 13  # capacity [N/m]; CAP_SHEAR 0: no shear spring
FREE_LENGTH = 14  # anchor: its length at the start; grouted: the debonded length [m]
RUPTURE = 15  # elongation at rupture over FREE_LENGTH [1]
AXIAL, SHEAR = 16, 17  # force now, tension > 0 [N/m]
SLIP_AXIAL, SLIP_SHEAR = 18, 19  # plastic displacement [m]
BROKEN = 20  # 1 once ruptured (carries nothing after)
YIELDED = 21  # 1 once it has reached its capacity
SUPPORT_COLUMNS = 22

# --- run clock: float64 (CLOCK_COLUMNS,) ------------------------------------------------------------
STEP, TIME, DT, SINCE_UPDATE = 0, 1, 2, 3
CLOCK_COLUMNS = 4

# --- kernel return codes --------------------------------------------------------------------------
DONE, SEARCH_NEEDED, STEP_ABOVE_CRITICAL, NO_BOUND = 0, 1, 2, 3
