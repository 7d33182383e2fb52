"""Index layout of the state vector, the body and element tables and the output row (numba constants).

State vector x (float64):
  positions  x[5*b + k]        body b = 0..6, k: 0 lateral y, 1 vertical z (m, relative to the track frame
                               at the body's station, + left / + up), 2 roll, 3 pitch, 4 yaw (rad,
                               relative to the track frame)
  velocities x[35 + 5*b + k]   k: 0 V_y, 1 V_z (absolute velocity of the body reference point, in track
                               axes), 2..4 absolute angular velocity about the track x, y, z axes
  dampers    x[70 + d]         elongation of the damper part of each series spring-damper element (m)
  position   x[78]             distance s of the car-body centre along the line (m)
Wheelsets: the k = 3 position entry (pitch angle) is unused and stays zero; the k = 3 velocity entry is the
wheelset's spin about its axle (rad/s, about v / r), a degree of freedom driven by the contact forces.
"""
N_BODY = 7
CAR_BODY = 0
BOGIES = (1, 2)               # front, rear
WHEELSETS = (3, 4, 5, 6)      # front to rear
N_DOF = 5
I_VEL = N_BODY * N_DOF        # 35
N_DAMPER = 8                  # 4 yaw dampers + 2 lateral dampers as mirrored pairs of halves
I_DAMPER = 2 * I_VEL          # 70
I_S = I_DAMPER + N_DAMPER     # 78
N_STATE = I_S + 1             # 79

# body table columns
B_MASS, B_IX, B_IY, B_IZ, B_STATION, B_HEIGHT, B_WHEELSET = 0, 1, 2, 3, 4, 5, 6
B_COLS = 7

# spring-damper "bushing" table (coincident points; stiffness and damping in the axes of body a)
E_A, E_B = 0, 1
E_PA = 2                      # 3 columns: point in body a coordinates (from its reference point)
E_PB = 5                      # 3 columns: the same point in body b coordinates
E_K = 8                       # 3 columns: stiffness x, y, z (N/m)
E_C = 11                      # 3 columns: damping x, y, z (N s/m)
E_F0 = 14                     # 3 columns: preload on body b, axes of a (N)
E_COLS = 17

# two-point damper table (force along the line between the points, optional series spring)
D_A, D_B, D_PA, D_PB = 0, 1, 2, 5
D_KNEE = 8                    # knee velocity (m/s)
D_C1 = 9                      # damping below the knee (N s/m)
D_C2 = 10                     # damping beyond the knee (N s/m)
D_KS = 11                     # series stiffness (N/m), 0 = none
D_L0 = 12                     # nominal length (m)
D_STATE = 13                  # index of its internal state in x
D_COLS = 14

# lateral bump stop table (points as for the bushing; force law in the vehicle parameter array)
S_A, S_B, S_PA, S_PB = 0, 1, 2, 5
S_COLS = 8

# anti-roll bar table
R_A, R_B, R_K = 0, 1, 2
R_COLS = 3

# vehicle parameter array vp
V_G = 0                       # gravity (m/s^2)
V_R0 = 1                      # nominal rolling radius (m)
V_SPIN_INERTIA = 2            # wheelset spin inertia (kg m^2)
V_BUMP_CLEARANCE = 3          # m
V_BUMP_N = 4                  # number of points of the bump-stop law
V_BUMP_TRAVEL = 5             # 8 slots
V_BUMP_FORCE = 13             # 8 slots
V_FLANGE_HEIGHT = 21          # m
V_CLIMB_DISPLACEMENT = 22     # lateral displacement that puts the flange tip over the rail top (m)
V_LIFT_TOLERANCE = 23         # m, see derailment criteria
V_SIZE = 24

# output row
O_T, O_S, O_V, O_SECTION, O_CURV, O_CANT, O_ANC = 0, 1, 2, 3, 4, 5, 6
O_BODY = 7                    # 7 x 5 body positions (as in the state)
O_WS = O_BODY + N_BODY * N_DOF          # per wheelset: lateral rel. to the rails, attack angle, roll
O_WS_COLS = 3
O_WHEEL = O_WS + 4 * O_WS_COLS          # 8 wheel records of contact.wheelset.W_SIZE
