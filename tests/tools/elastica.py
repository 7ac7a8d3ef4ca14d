import numpy as np
def shoot(alpha, k0, n=2000):
    # theta'' = -alpha cos(theta), theta(0)=0, theta'(0)=k0; returns theta'(1), x(1), y(1)
    h = 1.0 / n
    def f(y):  # y = (theta, kappa, x, y)
        return np.array([y[1], -alpha * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])])
    y = np.array([0.0, k0, 0.0, 0.0])
    for _ in range(n):
        a = f(y); b = f(y + h/2*a); c = f(y + h/2*b); d = f(y + h*c)
        y = y + h/6*(a + 2*b + 2*c + d)
    return y
def elastica(alpha):
    lo, hi = 0.0, alpha  # theta'(0) in (0, alpha]: the root moment PL(x_tip) <= PL
    for _ in range(60):
        mid = 0.5*(lo+hi)
        if shoot(alpha, mid)[1] > 0: hi = mid
        else: lo = mid
    y = shoot(alpha, 0.5*(lo+hi))
    return 1 - y[2], y[3]  # shortening, deflection (over L)
if __name__ == "__main__":
    for a in [1, 2, 3, 5]: print(a, elastica(a))
