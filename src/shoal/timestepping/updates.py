"""Per-particle update formulas of the time integrators (all backends).

Positions are float64 arrays in every precision: the displacement is
computed in the working precision and added in float64.

Fluid particles move; fixed boundary particles only update their density
(dynamic boundary condition, Crespo et al. 2007), which is kept >= rho0 so
that walls never attract fluid (as DualSPHysics does); walls whose density
is extrapolated from the fluid (``wall_pressure = "adami"`` or ``"mdbc"``)
keep it as the last rate evaluation set it. With XSPH the particles move
with v + dv_xsph.
"""

from ..physics.spec import FLUID


def make_updates(jit, spec, unpack):
    """Return a namespace-like dict of per-particle update functions."""
    F = spec.float_type
    dim = spec.dim
    half, two = F(0.5), F(2.0)
    use_xsph = spec.xsph

    keep_walls = spec.wall_pressure != 0

    @jit
    def clamp_bound(current, r, Parr):
        # walls whose density is extrapolated from the fluid (Adami, mDBC) keep the value of the
        # last rate evaluation: it is not integrated, and the snapshots show it
        if keep_walls:
            return current
        return max(r, unpack(Parr).rho0)

    @jit
    def verlet(i, pos, vel, rho, vel_m1, rho_m1, ace, drho, xsph, kind, dt, euler, Parr):
        """Verlet scheme (Verlet 1967) as in DualSPHysics, Euler step when `euler`:
        r^{n+1} = r^n + dt v^n + dt^2 a^n / 2
        v^{n+1} = v^{n-1} + 2 dt a^n     (Euler: v^n + dt a^n)
        rho^{n+1} = rho^{n-1} + 2 dt D^n (Euler: rho^n + dt D^n)"""
        if kind[i] == FLUID:
            for d in range(dim):
                v = vel[i, d]
                a = ace[i, d]
                vx = v + xsph[i, d] if use_xsph else v
                pos[i, d] += dt * vx + half * dt * dt * a
                vnew = v + dt * a if euler else vel_m1[i, d] + two * dt * a
                vel_m1[i, d] = v
                vel[i, d] = vnew
            r = rho[i]
            rnew = r + dt * drho[i] if euler else rho_m1[i] + two * dt * drho[i]
            rho_m1[i] = r
            rho[i] = rnew
        else:
            r = rho[i]
            rnew = r + dt * drho[i] if euler else rho_m1[i] + two * dt * drho[i]
            rho_m1[i] = r
            rho[i] = clamp_bound(rho[i], rnew, Parr)

    @jit
    def save_state(i, pos, vel, rho, pos_n, vel_n, rho_n):
        for d in range(dim):
            pos_n[i, d] = pos[i, d]
            vel_n[i, d] = vel[i, d]
        rho_n[i] = rho[i]

    @jit
    def half_step(i, pos, vel, rho, pos_n, vel_n, rho_n, ace, drho, xsph, kind, dt, Parr):
        """Predictor (both symplectic and predictor-corrector) over dt/2:
        r = r^n + dt/2 (v^n [+ dv_xsph]), v = v^n + dt/2 a^n, rho = rho^n + dt/2 D^n."""
        hdt = half * dt
        if kind[i] == FLUID:
            for d in range(dim):
                v0 = vel_n[i, d]
                vx = v0 + xsph[i, d] if use_xsph else v0
                pos[i, d] = pos_n[i, d] + hdt * vx
                vel[i, d] = v0 + hdt * ace[i, d]
            rho[i] = rho_n[i] + hdt * drho[i]
        else:
            rho[i] = clamp_bound(rho[i], rho_n[i] + hdt * drho[i], Parr)

    @jit
    def symplectic_correct(i, pos, vel, rho, pos_n, vel_n, rho_n, ace, drho, xsph, kind, dt, Parr):
        """Symplectic corrector (Leimkuhler 1996; DualSPHysics):
        v^{n+1} = v^n + dt a^{n+1/2},  r^{n+1} = r^n + dt (v^{n+1} + v^n)/2,
        rho^{n+1} = rho^n (2 - e)/(2 + e),  e = -(D^{n+1/2}/rho^{n+1/2}) dt."""
        e = -(drho[i] / rho[i]) * dt
        rnew = rho_n[i] * (two - e) / (two + e)
        if kind[i] == FLUID:
            for d in range(dim):
                v0 = vel_n[i, d]
                v1 = v0 + dt * ace[i, d]
                vm = half * (v1 + v0)
                vx = vm + xsph[i, d] if use_xsph else vm
                pos[i, d] = pos_n[i, d] + dt * vx
                vel[i, d] = v1
            rho[i] = rnew
        else:
            rho[i] = clamp_bound(rho[i], rnew, Parr)

    @jit
    def pc_correct(i, pos, vel, rho, pos_n, vel_n, rho_n, ace, drho, xsph, kind, dt, Parr):
        """Predictor-corrector corrector (Monaghan 1994, SPHysics):
        phi^{n+1/2} = phi^n + dt/2 F^{n+1/2}, then phi^{n+1} = 2 phi^{n+1/2} - phi^n,
        with positions advanced by v^{n+1/2} (+ XSPH)."""
        hdt = half * dt
        if kind[i] == FLUID:
            for d in range(dim):
                v0 = vel_n[i, d]
                vh = v0 + hdt * ace[i, d]
                vx = vh + xsph[i, d] if use_xsph else vh
                ph = pos_n[i, d] + hdt * vx
                pos[i, d] = two * ph - pos_n[i, d]
                vel[i, d] = two * vh - v0
            rh = rho_n[i] + hdt * drho[i]
            rho[i] = two * rh - rho_n[i]
        else:
            rh = rho_n[i] + hdt * drho[i]
            rho[i] = clamp_bound(rho[i], two * rh - rho_n[i], Parr)

    return dict(verlet=verlet, save_state=save_state, half_step=half_step, symplectic_correct=symplectic_correct,
                pc_correct=pc_correct)
