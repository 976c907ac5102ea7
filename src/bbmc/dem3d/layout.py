"""Column layout of the 3D engine's block array, and its degree-of-freedom codes.

One float64 row per block, ``blocks[i, VX]``; numba treats these module constants as compile-time
constants. SI throughout: m, s, kg, N, N m, rad.

Orientation is a unit quaternion q = (QW, QX, QY, QZ), scalar first, that turns the block's body frame
into the world: a point at b in the body frame is at x + R(q) b in the world. The body frame is the
block's principal frame (origin at the centroid, axes its principal axes of inertia), so the inertia in
it is diag(I1, I2, I3); the initial q is the quaternion of the principal-axes matrix R0 whose columns
are the principal axes in world coordinates (`motion.quaternion_from_matrix`).

Angular velocity (WX, WY, WZ), torques (TX, TY, TZ) and prescribed angular velocities are in the world
frame, as forces and velocities are: a contact reads v + w x r with r in world coordinates and adds
r x f, and a plane-strain twin (`bbmc.dem3d.extrusion`, extruded along y) holds rotation about the
world x and z axes. The motion kernel turns them into the principal frame where Euler's equations
are diagonal.
"""

# --- blocks: float64 (n_blocks, BLOCK_COLUMNS) -----------------------------------------------------
X, Y, Z = 0, 1, 2  # centroid [m]
QW, QX, QY, QZ = 3, 4, 5, 6  # orientation: unit quaternion, scalar first, body (principal) frame -> world
VX, VY, VZ = 7, 8, 9  # velocity at the last half step [m/s]
WX, WY, WZ = 10, 11, 12  # angular velocity at the last half step, world frame [rad/s]
FX, FY, FZ = 13, 14, 15  # force of the current step without gravity (contacts, loads) [N]
TX, TY, TZ = 16, 17, 18  # torque about the centroid of the current step, world frame [N m]
# (columns 0-18 are all a contact reads and writes of its two blocks)
MASS = 19  # true mass [kg]: gravity's weight, energies
I1, I2, I3 = 20, 21, 22  # true principal moments of inertia about the centroid [kg m^2]
MX, MY, MZ = 23, 24, 25  # inertial mass per translational degree of freedom [kg] (density scaling)
J1, J2, J3 = 26, 27, 28  # inertial principal moments [kg m^2] (density scaling may raise them)
VPX, VPY, VPZ = 29, 30, 31  # prescribed velocity of the prescribed translational dofs [m/s]
WPX, WPY, WPZ = 32, 33, 34  # prescribed angular velocity about the world axes [rad/s]
VSTART = 35  # step from which the prescribed velocities apply (before it, prescribed dofs are held)
PVX, PVY, PVZ = 36, 37, 38  # velocity of the half step before [m/s] (energies are read at full steps)
PWX, PWY, PWZ = 39, 40, 41  # angular velocity of the half step before, world frame [rad/s]
XR, YR, ZR = 42, 43, 44  # centroid at the last contact search [m]
QRW, QRX, QRY, QRZ = 45, 46, 47, 48  # orientation at the last contact search
RADIUS = 49  # largest distance from the centroid to a vertex [m]
BLOCK_COLUMNS = 50

# --- block degrees of freedom: int64 (n_blocks, 6): x, y, z, rotation about world x, y, z ------------
FREE, PRESCRIBED = 0, 1  # a fixed degree of freedom is one prescribed at zero velocity
DOFS = 6
