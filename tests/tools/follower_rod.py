"""A cantilever rod (inextensible, unshearable, length 1, bending stiffness 1) under a uniform
follower load of intensity alpha = q L^3 / EI per unit length, normal to the rod and pressing
on its upper side (the side of the normal n = (-sin theta, cos theta)): the large-deflection
solution that tests and the cantilever-hook example compare with.

The load follows the rod, so the whole solution turns with it: it is integrated once from the
free end (no force, no moment there, any angle), then turned and moved so that the root is at
the origin along x. Returns the tip displacement (u_x, u_y) over L and the tip angle."""
import math


def follower_rod(alpha, n=4000):
    # state along s from the tip (s = 1) to the root (s = 0): theta, M, F = (Fx, Fy), r = (x, y)
    def rhs(y):
        th, m, fx, fy, x, yy = y
        c, s = math.cos(th), math.sin(th)
        # d/ds of: theta' = M; M' = -(t x F); F' = q n (q = alpha, pressing: force -alpha n);
        # r' = t
        return [m, -(c * fy - s * fx), -alpha * s, alpha * c, c, s]
    h = -1.0 / n
    y = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    for _ in range(n):
        k1 = rhs(y)
        k2 = rhs([a + h / 2 * b for a, b in zip(y, k1)])
        k3 = rhs([a + h / 2 * b for a, b in zip(y, k2)])
        k4 = rhs([a + h * b for a, b in zip(y, k3)])
        y = [a + h / 6 * (b1 + 2 * b2 + 2 * b3 + b4) for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4)]
    th0, x0, y0 = y[0], y[4], y[5]
    # turn by -th0 about the root and move it to the origin: the tip (0, 0) goes to
    c, s = math.cos(-th0), math.sin(-th0)
    tx, ty = -x0, -y0
    return c * tx - s * ty - 1.0, s * tx + c * ty, -th0


if __name__ == "__main__":
    for a in [0.1, 1, 5, 10, 20, 30, 40]:
        ux, uy, th = follower_rod(a)
        print(a, ux, uy, math.degrees(th), "linear uy", -a / 8)
