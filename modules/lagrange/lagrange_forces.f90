!> Corner forces of the staggered scheme: pressure (Eq. 18), artificial
!> viscosity with a monotonic limiter, and viscous hourglass control. Also the
!> stable time step.
!>
!> Pressure. The corner force on node a is f_a = p dV/dx_a, the exact
!> gradient of the 24-tet volume (`mesh_geometry`); it equals -p times the
!> integral of n over the corner's share of the cell surface (Eq. 18) and
!> makes the compatible energy update (Eq. 19) reproduce p dV exactly.
!>
!> Artificial viscosity (deck: &hydro viscosity). Both forms act only where a
!> cell is compressed, heat only, and conserve momentum.
!>  - tensor (default): in the principal axes n_k of the cell's strain rate
!>    (exact velocity gradient from the volume gradient), every compressive
!>    axis gets a viscous pressure q_k = rho (1-phi_k)(c_quad du^2 + c_lin cs
!>    |du|), du = l_k lambda_k the jump over the cell's thickness l_k along
!>    n_k, acting as the stress -q_k n_k n_k. It does not depend on how the
!>    grid is oriented: on the 3D Sedov octant (20^3) the shock reaches
!>    r = 0.998 on the axes and 0.979 on the diagonal, against 1.059 and 0.961
!>    with the edge form.
!>  - edge: per logical direction d, with the median surface S_d and the mean
!>    velocity jump dv_d over the four d-edges, q_d acts along dv_d on the two
!>    d-sides (in the spirit of Caramana, Shashkov and Whalen 1998).
!> Limiter (Christensen 1990): phi = max(0, min(1, r_-, r_+)) with r_+- the
!> ratios of the neighbours' strain rate to the cell's own, so uniform
!> compression gets no viscosity and a shock full viscosity. For the tensor
!> form the neighbours are the two (of the 26) closest to the compression
!> axis n_k and the rate is the volumetric one: a shock crossing the grid
!> diagonally has its uncompressed neighbour across a cell corner, which the
!> face neighbours miss (with face neighbours the 40^3 Sedov density peaked at
!> 7.3 against the exact 6; with these it peaks at 6.3).
!>
!> Hourglass. Flanagan-Belytschko viscous control: with the hourglass base
!> vectors h (xi eta, eta zeta, zeta xi, xi eta zeta at the nodes) made
!> orthogonal to linear fields, gamma_a = h_a - (dV/dx_a . sum_b h_b x_b)/V,
!> f_a = -k rho cs A sum_modes gamma_a (sum_b gamma_b v_b); it sums to
!> zero, is dissipative and vanishes for any linear velocity field. A is the
!> mean of the three median areas (V^(2/3) for a cube). It is a damping
!> the step takes explicitly: a node whose eight cells share a mode (each
!> |gamma|^2 = 8 on a box) loses it at the rate lambda = 64 k cs A / V, and
!> the predictor-corrector multiplies the mode by 1 - lambda dt +
!> (lambda dt)^2/2 per step, which grows beyond lambda dt = 2, i.e. beyond
!> cs dt / dx = 1/(32 k) = 0.31 for k = 0.1. The acoustic step (Courant
!> number cfl over the Wilkins signal speed) stays below that only when the
!> linear viscosity is large enough (cfl 0.5 with q_linear 0.5: 0.309; with
!> q_linear 0.1: 0.45, where a TNT charge's shock in water grew the mode
!> 1.45-fold per step, tnt_water_pencil at 2 mm). So each cell's k is
!> lowered, where needed, to make its lambda dt (8 max_m |gamma_m|^2 k cs
!> A dt / V) at most 1.8, where the step still takes a fifth of the mode
!> away (factor 0.82); a cell whose lambda dt is below that is unchanged.
!> (A cap at 1, the fastest decay of that mode, lowers k in more cells, and
!> modes of a single cell, which see an eighth of lambda, then decay more
!> slowly: the LSSM Sedov of input/sedov3d_lssm.nml took 27 Euler steps
!> with it, against 14 with 1.8 and without a cap, its L1 2 % higher.) The
!> stable step is unchanged.
module lagrange_forces
  use, intrinsic :: iso_fortran_env, only: int8
  use base_kinds, only: wp
  use base_sym3, only: sym3_eigen
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_volume_gradient, hex_median_areas, hex_edges
  use hydro_state, only: hydro_t, hydro_params_t, VISC_TENSOR
  implicit none
  private
  public :: lagrange_node_flags, lagrange_cell_flags, lagrange_strain_rates, lagrange_corner_forces, lagrange_cell_rates, &
            lagrange_area_sizes, limiter_step

  !> Hourglass base vectors at the eight nodes, (node, mode).
  real(wp), parameter :: hg_base(8, 4) = reshape( &
    [ 1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp, &
      1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp,  1.0_wp, &
      1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp,  1.0_wp, &
     -1.0_wp,  1.0_wp,  1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp], [8, 4])

contains

  !> Mean jump of a node field across the cell in logical direction d:
  !> the average over the four d-edges of (high node - low node).
  pure function edge_jump(vn, d) result(dv)
    real(wp), intent(in) :: vn(3, 8)
    integer, intent(in) :: d
    real(wp) :: dv(3)
    integer :: e
    dv = 0.0_wp
    do e = 1, 4
      dv = dv + vn(:, hex_edges(2, e, d)) - vn(:, hex_edges(1, e, d))
    end do
    dv = 0.25_wp*dv
  end function edge_jump

  !> Christensen-type limiter from the strain rates of a cell and its two
  !> neighbours in one direction: 1 (no viscosity) unless the cell is
  !> compressed and its neighbours are not compressed alike.
  pure function limiter(gself, gm, gp) result(phi)
    real(wp), intent(in) :: gself, gm, gp
    real(wp) :: phi, rm, rp
    if (.not. (gself < 0.0_wp)) then
      phi = 1.0_wp
      return
    end if
    rm = gm/gself
    rp = gp/gself
    phi = max(0.0_wp, min(1.0_wp, rm, rp))
  end function limiter

  !> The logical step off (each component -1, 0 or 1) from a cell to the
  !> neighbour, among the 26, that lies closest to the direction n, from the
  !> cell's median-surface area vectors s(:, d): going along n crosses the
  !> cell's logical direction d at the rate n . s(:, d) / V (exact for a
  !> parallelepiped), and off is that rate vector scaled to a largest
  !> component of 1, rounded. In the cell's own axes, not the coordinate
  !> axes, which name other neighbours on a rotated, sheared or stretched
  !> grid (read in the coordinate axes, the paper's Sedov with LSSM at 20^3,
  !> whose smoothing leaves sheared cells, peaked at density 9.8 against
  !> the exact 6; 7.4 with this).
  pure function limiter_step(s, n) result(off)
    real(wp), intent(in) :: s(3, 3), n(3)
    integer :: off(3)
    real(wp) :: xi(3)
    xi = matmul(n, s)
    off = nint(xi/maxval(abs(xi)))
  end function limiter_step

  !> Tensor viscosity in the principal axes of the strain rate D = sym(grad v)
  !> (grad v = (1/V) sum_a v_a (x) dV/dx_a, exact for linear fields). For each
  !> compressive principal direction n_k (eigenvalue lambda_k < 0) of a cell
  !> whose volume shrinks, the jump across the cell along n_k is
  !> du_k = l_k lambda_k with l_k = V / sum_d |S_d . n_k| its thickness along
  !> n_k, and q_k = rho (1 - phi_k)(c_quad du_k^2 + c_lin cs |du_k|) acts as the
  !> stress -q_k n_k n_k: f_a = q_k n_k (n_k . dV/dx_a). The forces sum to zero,
  !> their work is -sum_k q_k V lambda_k >= 0, and the result does not depend
  !> on how the grid is oriented with respect to the shock. phi_k is the
  !> limiter along n_k (see lagrange_corner_forces); sc scales q_k (1 - theta_c
  !> in cells hosting particles, else 1: x 1 is exact).
  pure subroutine tensor_viscosity(b, vol, s, lam, ev, phik, rho, cs, par, sc, f, qsum)
    real(wp), intent(in) :: b(3, 8), vol, s(3, 3), lam(3), ev(3, 3), phik(3), rho, cs, sc
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(inout) :: f(3, 8)
    real(wp), intent(out) :: qsum
    real(wp) :: n(3), len_k, du, qk
    integer :: a, k

    qsum = 0.0_wp
    do k = 1, 3
      if (.not. (lam(k) < 0.0_wp)) cycle
      n = ev(:, k)
      len_k = vol/sum(abs(matmul(n, s)))
      du = len_k*lam(k)
      qk = sc*(rho*(1.0_wp - phik(k))*(par%q_quad*du*du - par%q_linear*cs*du))
      qsum = qsum + qk
      do a = 1, 8
        f(:, a) = f(:, a) + (qk*dot_product(n, b(:, a)))*n
      end do
    end do
  end subroutine tensor_viscosity

  !> Velocity gradient (1/V) sum_a v_a (x) dV/dx_a of a cell (exact for linear
  !> fields), its divergence, and the principal strain rates lam and axes ev
  !> of its symmetric part; div is returned as 0 (and nothing else computed)
  !> unless the cell is compressed faster than div_min.
  pure subroutine strain_principal(vn, b, vol, div_min, div, lam, ev)
    real(wp), intent(in) :: vn(3, 8), b(3, 8), vol, div_min
    real(wp), intent(out) :: div, lam(3), ev(3, 3)
    real(wp) :: gv(3, 3)
    integer :: a, i, j
    gv = 0.0_wp
    do a = 1, 8
      do j = 1, 3
        do i = 1, 3
          gv(i, j) = gv(i, j) + vn(i, a)*b(j, a)
        end do
      end do
    end do
    gv = gv/vol
    div = gv(1, 1) + gv(2, 2) + gv(3, 3)
    if (.not. (div < -div_min)) then
      div = 0.0_wp
      lam = 0.0_wp
      ev = 0.0_wp
      return
    end if
    call sym3_eigen(0.5_wp*(gv + transpose(gv)), lam, ev)
  end subroutine strain_principal

  !> The cell at logical offset off from cell c = (ilog), or c itself where
  !> that leaves the stored cells (a mirror neighbour, as at a symmetry plane;
  !> ghosts are stored two deep, so an owned cell and the ghost layer next
  !> to it find their neighbours).
  pure integer function neighbour(g, c, ilog, off)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: c, ilog(3), off(3)
    if (any(ilog + off < g%slo) .or. any(ilog + off > g%shi)) then
      neighbour = c
    else
      neighbour = g%cell(ilog(1) + off(1), ilog(2) + off(2), ilog(3) + off(3))
    end if
  end function neighbour

  !> Strain rates of one cell from its node velocities vn(3,8), median-surface
  !> area vectors s(3,3) (`hex_median_areas`) and volume vol: the areas
  !> area(d) = |S_d| (length^2), the directional strain rates
  !> grad(d) = S_d.dv_d / V (1/time; dv_d the mean velocity jump along d) and
  !> dumax, the largest compressive jump -S_d.dv_d/|S_d| (velocity; 0 if none).
  pure subroutine lagrange_cell_rates(vn, s, vol, area, grad, dumax)
    real(wp), intent(in) :: vn(3, 8), s(3, 3), vol
    real(wp), intent(out) :: area(3), grad(3), dumax
    real(wp) :: dv(3), sdv
    integer :: d
    dumax = 0.0_wp
    do d = 1, 3
      dv = edge_jump(vn, d)
      area(d) = norm2(s(:, d))
      sdv = dot_product(s(:, d), dv)
      grad(d) = sdv/vol
      dumax = max(dumax, -(sdv/max(area(d), tiny(1.0_wp))))
    end do
  end subroutine lagrange_cell_rates

  !> The largest and the sum of a cell's three median-surface areas
  !> area(3) (length^2; `lagrange_cell_rates`), as h%amed keeps them.
  pure function lagrange_area_sizes(area) result(sizes)
    real(wp), intent(in) :: area(3)
    real(wp) :: sizes(2)
    integer :: d
    sizes(1) = 0.0_wp
    do d = 1, 3
      sizes(1) = max(sizes(1), area(d))
    end do
    sizes(2) = area(1) + area(2) + area(3)
  end function lagrange_area_sizes

  !> Directional strain rates g(d,c) = S_d.dv_d / V of every cell for the
  !> velocity v, and the largest stable step for that state (CFL on sound
  !> speed plus viscous signal speed, and a bound on the relative volume change).
  !> In a mixed cell the sound speed is the largest of its materials'
  !> (`mixed_cell_state`), and when the cell is compressed the volume bound
  !> holds for each material's share of the cell's change too:
  !> dt <= dv_max / (gain |div|), h%gain from `mixed_volume_gain` (a soft
  !> material takes more than its fraction, and could otherwise collapse in
  !> one step; an expanding cell shrinks none of its materials).
  !> x must be the positions whose cell volumes are h%vol. Also keeps the
  !> volume gradient and median-area sizes of x that `lagrange_corner_forces`
  !> needs (h%dvdx, h%amed), so that the forces of the same x, v do not
  !> compute them again.
  !> `dt_cell` (optional) returns the cell that limits the step: the lowest
  !> cell index among those whose own step equals dt_stable (0 if no cell
  !> limits it), the same for any thread count. Each thread keeps its own
  !> minimum and the first cell (in its increasing cell order) that reaches
  !> it; the threads' pairs are then combined by (step, cell). min is exact,
  !> so dt_stable is the same number as with a plain min reduction.
  subroutine lagrange_strain_rates(g, x, v, h, par, dt_stable, dt_cell)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), v(:, :)
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(out) :: dt_stable
    integer, intent(out), optional :: dt_cell
    integer :: c, d, e, n0, ci, cj, ck, c_min, c_loc
    real(wp) :: xn(3, 8), vn(3, 8), s(3, 3), area(3), vol, amax, dumax, div, cq, ceff, dtc, dt_loc

    dt_stable = huge(1.0_wp)
    c_min = 0
    ! (`at_rest`: bit 1, a velocity; bit 2, a node away from its step's start)
    call lagrange_node_flags(h%nflag, v, 1_int8, .true.)
    call lagrange_node_flags(h%nflag, x, 2_int8, .false., h%xn)
    !$omp parallel default(none) shared(g, x, v, h, par, dt_stable, c_min) &
    !$omp private(c, d, e, n0, ci, cj, ck, xn, vn, s, area, vol, amax, dumax, div, cq, ceff, dtc, dt_loc, c_loc)
    dt_loc = huge(1.0_wp)
    c_loc = 0
    !$omp do collapse(2) schedule(static)
    do ck = g%slo(3), g%shi(3)
    do cj = g%slo(2), g%shi(2)
    ! consecutive i are consecutive cells and nodes
    c = g%cell(g%slo(1), cj, ck) - 1
    n0 = g%cell_node0(g%slo(1), cj, ck) - 1
    do ci = g%slo(1), g%shi(1)
      c = c + 1
      n0 = n0 + 1
      if (at_rest(g, h, n0, c)) then
        ! (geometry, rates and sizes as the last step left them: at these
        ! places at rest, `at_rest`; what the calls below give again)
        dumax = 0.0_wp
      else
        do e = 1, 8
          xn(:, e) = x(1:3, n0 + g%corner_offset(e))
          vn(:, e) = v(1:3, n0 + g%corner_offset(e))
        end do
        ! vol equals h%vol(c) (the same sum (*) of mesh_geometry), which is used
        call hex_volume_gradient(xn, vol, h%dvdx(1:3, 1:8, c))
        call hex_median_areas(xn, s)
        call lagrange_cell_rates(vn, s, h%vol(c), area, h%grad(1:3, c), dumax)
        h%amed(1:2, c) = lagrange_area_sizes(area)
        ! (these are no longer the step start's: `lagrange_update_cells`
        ! says again whether the cell is at rest)
        h%still(c) = .false.
      end if
      amax = h%amed(1, c)
      div = 0.0_wp
      do d = 1, 3
        div = div + h%grad(d, c)
      end do
      ! signal speed with viscosity: cq + sqrt(cq^2 + cs^2) (Wilkins)
      cq = par%q_linear*h%cs(c) + par%q_quad*dumax
      ceff = cq + sqrt(cq*cq + h%cs(c)**2)
      dtc = huge(1.0_wp)
      ! (a signal speed below 1e-100 cell widths per unit time, a cold gas
      ! at rest, sets no limit: the quotient would overflow)
      if (ceff > 1.0e-100_wp*(h%vol(c)/amax)) dtc = par%cfl*(h%vol(c)/amax)/ceff
      ! (a rate so small that dv_max/|div| would overflow sets no limit)
      if (abs(div) > 2.0_wp*par%dv_max/huge(1.0_wp)) then
        dtc = min(dtc, par%dv_max/abs(div))
        if (h%mat(c) < 0 .and. div < 0.0_wp) dtc = min(dtc, par%dv_max/(h%gain(c)*abs(div)))
      end if
      ! (the step of a ghost cell is its owner's to take)
      if (g%ng > 0) then
        if (.not. g%owns_cell(ci, cj, ck)) cycle
      end if
      if (dtc < dt_loc) c_loc = c
      dt_loc = min(dt_loc, dtc)
    end do
    end do
    end do
    !$omp end do nowait
    !$omp critical (lagrange_dt_min)
    if (c_loc > 0) then
      if (dt_loc < dt_stable) then
        c_min = c_loc
      else if (.not. dt_loc > dt_stable .and. (c_min == 0 .or. c_loc < c_min)) then
        c_min = c_loc   ! a tie: the lower cell index
      end if
    end if
    dt_stable = min(dt_stable, dt_loc)
    !$omp end critical (lagrange_dt_min)
    !$omp end parallel
    if (present(dt_cell)) dt_cell = c_min
  end subroutine lagrange_strain_rates

  !> Whether cell c (its first node n0; h%nflag as `lagrange_strain_rates`
  !> sets it) is at rest where the last step left it: h%still (at rest in that
  !> step's first stage, at the places it began with: h's geometry, rates
  !> and sizes are those of h%xn at rest), and every node still there and
  !> at rest. Its geometry (h%dvdx, h%amed, h%vol) and rates (h%grad) are
  !> then those of these places and velocities (zero rates may differ in
  !> the sign of a zero, which no test reads). (The places are compared:
  !> an Euler step may have moved them since.)
  pure logical function at_rest(g, h, n0, c)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    integer, intent(in) :: n0, c
    at_rest = h%still(c)
    if (at_rest) at_rest = lagrange_cell_flags(g, h%nflag, n0) == 0
  end function at_rest

  !> Bits of each stored node n (nflag(n), its entries 1..size(v, 2)):
  !> with y absent, bit is set where v(:, n) has a component of nonzero
  !> size (abs > 0, which a NaN is not), with y where v(:, n) differs from
  !> y(:, n) so (abs(v - y) > 0); clear: the other bits are cleared first.
  !> The cell loops of the kernels read their eight nodes' bits
  !> (`lagrange_cell_flags`) instead of testing 24 or 48 reals each.
  subroutine lagrange_node_flags(nflag, v, bit, clear, y)
    integer(int8), intent(inout) :: nflag(:)
    real(wp), intent(in) :: v(:, :)
    integer(int8), intent(in) :: bit
    logical, intent(in) :: clear
    real(wp), intent(in), optional :: y(:, :)
    integer :: n
    integer(int8) :: keep
    ! (the bits kept: none with clear)
    keep = merge(0_int8, not(bit), clear)
    ! (branch-free loops, which the compiler runs in vector lanes)
    if (present(y)) then
      !$omp parallel do default(none) shared(nflag, v, bit, keep, y) private(n) schedule(static)
      do n = 1, size(v, 2)
        nflag(n) = ior(iand(nflag(n), keep), merge(bit, 0_int8, abs(v(1, n) - y(1, n)) > 0.0_wp .or. &
                                              abs(v(2, n) - y(2, n)) > 0.0_wp .or. abs(v(3, n) - y(3, n)) > 0.0_wp))
      end do
      !$omp end parallel do
    else
      !$omp parallel do default(none) shared(nflag, v, bit, keep) private(n) schedule(static)
      do n = 1, size(v, 2)
        nflag(n) = ior(iand(nflag(n), keep), merge(bit, 0_int8, abs(v(1, n)) > 0.0_wp .or. abs(v(2, n)) > 0.0_wp .or. &
                                                                 abs(v(3, n)) > 0.0_wp))
      end do
      !$omp end parallel do
    end if
  end subroutine lagrange_node_flags

  !> The bits of the eight nodes of the cell whose first node is n0, or-ed
  !> (`lagrange_node_flags`).
  pure integer(int8) function lagrange_cell_flags(g, nflag, n0) result(bits)
    type(grid_t), intent(in) :: g
    integer(int8), intent(in) :: nflag(:)
    integer, intent(in) :: n0
    integer :: a
    bits = 0_int8
    do a = 1, 8
      bits = ior(bits, nflag(n0 + g%corner_offset(a)))
    end do
  end function lagrange_cell_flags

  !> Corner forces fc(3,8,c) from the positions x, velocities v and the cell
  !> pressures in h; needs h%grad and the cell geometry (h%vol, h%dvdx,
  !> h%amed) of the same x, v, as left by `lagrange_strain_rates`
  !> or by `lagrange_update_cells` with `geometry`. vscale (ncell, optional):
  !> a factor on each cell's artificial viscosity (1 - theta_c of the
  !> particles, PARTICLES.md §1.7; h%q is the scaled one); without it the
  !> factor is 1, and a product with 1 is exact, so the forces are the same
  !> bit for bit.
  subroutine lagrange_corner_forces(g, x, v, h, par, vscale, dt)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), v(:, :)
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in), optional, target :: vscale(:)
    !> the step the forces advance: a compression that changes the cell's
    !> size by less than round_strain over it (a velocity jump of round-off
    !> size, as in a cold gas ahead of a shock, where velocities of 1e-75
    !> drift in the last bits) gets no viscosity; its viscous force,
    !> computed from one stage's velocities and paid with another's, could
    !> take more than such a cell's energy and leave it below zero
    real(wp), intent(in), optional :: dt
    integer :: c, d, e, a, k, m, n0, ci, cj, ck, ilog(3), off(3)
    integer, parameter :: unit(3, 3) = reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3])
    real(wp) :: xn(3, 8), vn(3, 8), b(3, 8), f(3, 8), s(3, 3), dv(3), lam(3), ev(3, 3), phik(3)
    real(wp) :: vol, rvol, sdv, area, du, qd, qsum, coef, hx(3), gam(8, 4), gv(3, 4), phi, div, sc, ggmax, hgdt
    real(wp), target :: one(1)
    real(wp), pointer :: scale(:)
    integer :: sstride, lo(3), hi(3)
    real(wp), parameter :: round_strain = 1.0e-12_wp, hg_round = 1.0e-30_wp, hg_zmax = 1.8_wp
    real(wp) :: rate_min, dt_hg
    ! the owned cells and one ghost layer: every cell around an owned node
    call g%cells_around(1, lo, hi)
    ! (without vscale every cell reads the one factor 1)
    one = 1.0_wp
    scale => one
    sstride = 0
    if (present(vscale)) then
      scale => vscale
      sstride = 1
    end if
    ! (the smallest strain rate a viscosity sees: none without dt)
    rate_min = 0.0_wp
    dt_hg = 0.0_wp
    if (present(dt)) then
      if (dt > 0.0_wp) rate_min = round_strain/dt
      dt_hg = max(dt, 0.0_wp)
    end if

    ! (bit 1: a node's velocity)
    call lagrange_node_flags(h%nflag, v, 1_int8, .true.)
    ! rows dealt round-robin: the costly compressed cells gather in a shock
    ! shell, which a blocked schedule would give to one thread
    !$omp parallel do default(none) shared(g, x, v, h, par, scale, sstride, lo, hi, rate_min, dt_hg) collapse(2) &
    !$omp private(c, d, e, a, k, m, n0, ci, cj, ck, ilog, off, xn, vn, b, f, s, dv, lam, ev, phik) &
    !$omp private(vol, rvol, sdv, area, du, qd, qsum, coef, hx, gam, gv, phi, div, sc, ggmax, hgdt) &
    !$omp schedule(static, 1)
    do ck = lo(3), hi(3)
    do cj = lo(2), hi(2)
    ! consecutive i are consecutive cells and nodes
    c = g%cell(lo(1), cj, ck) - 1
    n0 = g%cell_node0(lo(1), cj, ck) - 1
    do ci = lo(1), hi(1)
      c = c + 1
      n0 = n0 + 1
      if (lagrange_cell_flags(g, h%nflag, n0) == 0) then
        ! (a cell at rest: no viscosity, no hourglass mode; what the terms
        ! below give with vn = 0, without their cost; Eq. 18)
        h%q(c) = 0.0_wp
        b = h%dvdx(1:3, 1:8, c)
        h%fc(1:3, 1:8, c) = h%p(c)*b
        cycle
      end if
      do a = 1, 8
        xn(:, a) = x(1:3, n0 + g%corner_offset(a))
        vn(:, a) = v(1:3, n0 + g%corner_offset(a))
      end do
      vol = h%vol(c)
      sc = scale(1 + sstride*(c - 1))
      b = h%dvdx(1:3, 1:8, c)
      ! Eq. (18): pressure corner forces
      f = h%p(c)*b

      ! artificial viscosity with limiter (the median-surface area vectors,
      ! a few dozen flops, are computed where a viscosity needs them: kept
      ! per cell they would cost 72 bytes; their norms' largest and sum are
      ! kept, h%amed)
      ilog = [ci, cj, ck]
      qsum = 0.0_wp
      if (par%viscosity == VISC_TENSOR) then
        ! skip cells whose compression is round-off: a velocity jump below
        ! 1e-10 of the sound speed gives q below 1e-10 of the pressure; a
        ! compression below round_strain over the step is none
        call strain_principal(vn, b, vol, max(h%cs(c)*1.0e-10_wp*h%amed(1, c)/vol, rate_min), div, lam, ev)
        if (div < 0.0_wp) then
          call hex_median_areas(xn, s)
          ! limiter along each compressive principal direction: compare the
          ! volumetric strain rate with the two neighbours (among the 26)
          ! that lie closest to that direction
          do k = 1, 3
            phik(k) = 1.0_wp
            if (.not. (lam(k) < 0.0_wp)) cycle
            off = limiter_step(s, ev(:, k))
            phik(k) = limiter(sum(h%grad(1:3, c)), &
                              sum(h%grad(1:3, neighbour(g, c, ilog, -off))), &
                              sum(h%grad(1:3, neighbour(g, c, ilog, off))))
          end do
          call tensor_viscosity(b, vol, s, lam, ev, phik, h%rho(c), h%cs(c), par, sc, f, qsum)
        end if
      else
        call hex_median_areas(xn, s)
        do d = 1, 3
          dv = edge_jump(vn, d)
          sdv = dot_product(s(:, d), dv)
          ! (sdv/vol: the compression rate along d; below rate_min, none)
          if (.not. (sdv < -rate_min*vol)) cycle
          phi = limiter(h%grad(d, c), h%grad(d, neighbour(g, c, ilog, -unit(:, d))), &
                        h%grad(d, neighbour(g, c, ilog, unit(:, d))))
          du = norm2(dv)
          area = abs(sdv)/du
          qd = sc*(h%rho(c)*(1.0_wp - phi)*(par%q_quad*du*du + par%q_linear*h%cs(c)*du))
          qsum = qsum + qd
          ! force along -dv on the high side, +dv on the low side
          dv = (0.25_wp*qd*area/du)*dv
          do e = 1, 4
            f(:, hex_edges(2, e, d)) = f(:, hex_edges(2, e, d)) - dv
            f(:, hex_edges(1, e, d)) = f(:, hex_edges(1, e, d)) + dv
          end do
        end do
      end if
      h%q(c) = qsum

      ! Flanagan-Belytschko viscous hourglass control
      if (par%hourglass > 0.0_wp) then
        ! length^2 scale: the mean median area (V^(2/3) for a cube, without a pow)
        coef = par%hourglass*h%rho(c)*h%cs(c)*h%amed(2, c)/3.0_wp
        rvol = 1.0_wp/vol
        ggmax = 0.0_wp
        do m = 1, 4
          hx = 0.0_wp
          do a = 1, 8
            hx = hx + hg_base(a, m)*xn(:, a)
          end do
          gv(:, m) = 0.0_wp
          do a = 1, 8
            gam(a, m) = hg_base(a, m) - dot_product(b(:, a), hx)*rvol
            gv(:, m) = gv(:, m) + gam(a, m)*vn(:, a)
          end do
          ggmax = max(ggmax, sum(gam(:, m)**2))
        end do
        ! the damping's rate times the step, 8 max |gamma|^2 dt coef/(rho V),
        ! at most hg_zmax (the header)
        hgdt = 8.0_wp*ggmax*(par%hourglass*h%cs(c)*h%amed(2, c)/3.0_wp)*dt_hg*rvol
        if (hgdt > hg_zmax) coef = coef*(hg_zmax/hgdt)
        do m = 1, 4
          ! (a mode below 1e-30 of the sound speed is none: ahead of a wave
          ! the force would carry a precursor down to subnormal numbers)
          if (.not. any(abs(gv(:, m)) > hg_round*h%cs(c))) cycle
          do a = 1, 8
            f(:, a) = f(:, a) - coef*gam(a, m)*gv(:, m)
          end do
        end do
      end if
      h%fc(1:3, 1:8, c) = f
    end do
    end do
    end do
    !$omp end parallel do
  end subroutine lagrange_corner_forces
end module lagrange_forces
