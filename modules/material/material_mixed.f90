!> Mixed cells: cells that hold more than one material, stored compactly.
!>
!> Only mixed cells have per-material data, in compressed rows: mixed cell k
!> is grid cell `cell(k)` and owns the slots start(k) .. start(k+1)-1, one per
!> material present, each with that material's volume fraction, mass,
!> specific internal energy, density, pressure, sound speed and centroid (in
!> the cell's natural coordinates, so it moves with a Lagrangian cell; the MoF
!> interface reconstruction of the remap uses it as its reference). Each slot
!> also keeps the plane, in natural coordinates, that bounds its material in
!> the nested dissection of the cell (`lagrange_centroids` keeps
!> centroids and planes consistent with the volume fractions between remaps).
!> A scene without mixed cells has n = 0 and never enters this module's loops.
!>
!> Pressure closure (Tipton; Shashkov 2008, the paper's ref. [68]): over a
!> step the cell's volume change dV is shared as dV_m = f_m dV + theta d_m,
!> where d_m (sum zero) is the exchange that brings the linearised material
!> pressures p_m - B_m dV_m/V_m (B_m = rho_m c_m^2) to a common value
!>   pbar = (sum_m (V_m/B_m) p_m - dV) / sum_m (V_m/B_m),
!>   d_m  = (V_m/B_m) (p_m - B_m dV/V - pbar),
!> and theta in (0, 1] (deck: &hydro relax) is how much of the way the step
!> goes, reduced where needed so that no material loses more than 90 % of
!> its volume in one step, nor is compressed by the exchange by more than
!> dv_max (&hydro) of it: the linearised pressure is only valid for small strains (water
!> beside a JWL product at 8 GPa was otherwise crushed to a third of its
!> volume in one step, its Mie-Gruneisen pressure then ran to hundreds of
!> GPa and its energy to -4800 kJ/g; issue 36). The rest of the way is
!> taken over the following steps.
!>
!> Cavitated materials. A material whose pressure is at its floor (p_min,
!> its cut-off: water that cannot hold tension) at the step's start gives
!> no resistance to growth: where it grows its B is 0, not the rho c^2 of
!> its EOS. The limit of the weights V/B is taken exactly (`cavitated`):
!> the common pressure is the floor's, the other materials relax to it
!> (their linearised pressures kept above min(p, 0) by `no_tension`) and
!> the cavitated ones take the rest of the cell's change by volume. Under
!> compression it is as stiff as its EOS says (the cut-off model's cavity is
!> only its elastic stretch below the floor). Before, a trace of products
!> beside cavitated water took all of an expanding cell's growth, and the
!> time step of such a cell collapsed (issue 36: hardcases/tnt_surface.nml
!> at 30 x 30 x 75, Eulerian, stalled at dt 3e-4 us).
!>
!> Acoustic resistance (Tipton's closure; &hydro relax_length). In the
!> weights B_m above, not in the material's own linearised pressure, each
!> material adds eta_m = Z_m L_m / dt, Z_m = rho_m c_m its impedance and
!> L_m = relax_length f_m V/A its thickness (A the cell's largest
!> median-surface area, V/A the cell's thickness). For two materials and a
!> fixed cell the exchange is then the acoustic Riemann problem's: the
!> common pressure is (Z_2 p_1 + Z_1 p_2)/(Z_1 + Z_2), the interface moves
!> at (p_1 - p_2)/(Z_1 + Z_2), and a pressure difference relaxes over the
!> time sound takes to cross the materials' layers rather than in one step;
!> the cell's compression is shared by impedance over a short step, by
!> compressibility over a long one. With it a gas beside a dense product
!> has by far the larger weight, and an expanding cell would give it all
!> of its growth at a negative pressure: an expanding material's linearised
!> pressure is kept above min(p_m, 0) (`no_tension`), the rest of the
!> growth going to the others. Each material
!> does the work of its own (linearised, mid-step) pressure, -p~_m dV_m; the
!> rest of the cell's energy change from the compatible update (viscous and
!> hourglass heating, linearisation error) is shared by mass, so the cell's
!> total energy is exactly the compatible one (Eq. 19).
!>
!> Time step (`mixed_volume_gain`). The dt-dependent part of a material's
!> volume change is its share of the cell's, (1 - theta) f_m dV +
!> theta (V_m/B_m)/S dV with S = sum_k V_k/B_k: relative to its own volume,
!> a soft material in a stiff one changes by up to 1/f_m times the cell's
!> relative change (an air bubble in water takes all of the cell's
!> compression). When the cell is compressed the stable step limits that
!> relative change per step (`lagrange_strain_rates`) as it limits the
!> cell's, so that no material collapses in one step and the 90 % cap above
!> is a safeguard rather than the rule. (An expanding cell shrinks none of
!> its materials through this part; the part that equalises the pressures,
!> theta d_m, does not scale with dt and is left to the cap.)
module material_mixed
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_registry, only: registry_t, LOC_MIXED_CELL, LOC_MIXED_SLOT, LOWER_POSITIVE, LOWER_NONNEGATIVE
  implicit none
  private
  public :: mixed_t, mixed_allocate, mixed_save_step_start, mixed_split, mixed_cell_state, mixed_register_restart, &
            mixed_forget_planes, mixed_volume_gain, mixed_subset

  !> Compressed storage of the mixed cells.
  type :: mixed_t
    integer :: n = 0                      !< number of mixed cells
    integer :: nslot = 0                  !< number of (cell, material) slots
    integer, allocatable :: cell(:)       !< grid cell of mixed cell k (n)
    integer, allocatable :: start(:)      !< first slot of mixed cell k (n+1)
    integer, allocatable :: mat(:)        !< material of each slot (nslot)
    real(wp), allocatable :: vf(:)        !< volume fraction
    real(wp), allocatable :: mass(:)      !< material mass in the cell
    real(wp), allocatable :: e(:)         !< specific internal energy
    real(wp), allocatable :: rho(:)       !< material density
    real(wp), allocatable :: p(:)         !< material pressure
    real(wp), allocatable :: cs(:)        !< material sound speed
    !> material centroid, natural coordinates in [-1,1]^3 (3, nslot); where
    !> the planes below are known it is that of the plane cutting the
    !> current fraction as of the last `centroids_refresh` (before each remap
    !> and dump), the planes carrying it in between
    real(wp), allocatable :: xi(:, :)
    !> the plane n.xi <= d that bounds the slot's material in the nested
    !> dissection of its cell (slot order), in natural coordinates (the
    !> cell's map taken affine about its centre): (n(1:3), d) with |n| = 1,
    !> (4, nslot); the last slot of a cell has none (n = 0). A cell whose
    !> other slots have n = 0: not known (`lagrange_centroids` fits it by MoF)
    real(wp), allocatable :: plane(:, :)
    ! state at the start of the step
    real(wp), allocatable :: vfn(:), en(:), pn(:), bn(:), voln(:)
  end type mixed_t

contains

  !> Allocates storage for n mixed cells with nslot slots in all.
  subroutine mixed_allocate(mx, n, nslot, err)
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: n, nslot
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    mx%n = n
    mx%nslot = nslot
    allocate(mx%cell(n), mx%start(n + 1), mx%mat(nslot), mx%vf(nslot), mx%mass(nslot), &
             mx%e(nslot), mx%rho(nslot), mx%p(nslot), mx%cs(nslot), mx%xi(3, nslot), mx%plane(4, nslot), &
             mx%vfn(nslot), mx%en(nslot), mx%pn(nslot), mx%bn(nslot), mx%voln(n), &
             stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'mixed_allocate', error_no_memory('mixed cells'))
      return
    end if
    mx%start(1) = 1
    mx%xi = 0.0_wp
    mx%plane = 0.0_wp
    mx%p = 0.0_wp
    mx%cs = 0.0_wp
  end subroutine mixed_allocate

  !> The mixed cells pick(1..m) of mx, in that order, as cells cell(1..m) of
  !> another numbering (a block's cells as the whole grid's, or the reverse):
  !> every stored quantity of their slots copied (the step-start values are
  !> set at each step and are not).
  subroutine mixed_subset(mx, pick, cell, out, err)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: pick(:), cell(:)
    type(mixed_t), intent(out) :: out
    type(error_t), allocatable, intent(inout) :: err
    integer :: q, k, s0, s1, ns
    ns = 0
    do q = 1, size(pick)
      ns = ns + mx%start(pick(q) + 1) - mx%start(pick(q))
    end do
    call mixed_allocate(out, size(pick), ns, err)
    if (allocated(err)) return
    do q = 1, size(pick)
      k = pick(q)
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      out%cell(q) = cell(q)
      out%start(q + 1) = out%start(q) + s1 - s0 + 1
      associate (t0 => out%start(q), t1 => out%start(q + 1) - 1)
        out%mat(t0:t1) = mx%mat(s0:s1)
        out%vf(t0:t1) = mx%vf(s0:s1)
        out%mass(t0:t1) = mx%mass(s0:s1)
        out%e(t0:t1) = mx%e(s0:s1)
        out%rho(t0:t1) = mx%rho(s0:s1)
        out%p(t0:t1) = mx%p(s0:s1)
        out%cs(t0:t1) = mx%cs(s0:s1)
        out%xi(:, t0:t1) = mx%xi(:, s0:s1)
        out%plane(:, t0:t1) = mx%plane(:, s0:s1)
      end associate
    end do
  end subroutine mixed_subset

  !> Forgets the interface planes of every mixed cell (after a remap has
  !> built new mixed cells: their centroids are those of the remapped
  !> material, their planes not yet known); the storage is sized to nslot.
  subroutine mixed_forget_planes(mx, err)
    type(mixed_t), intent(inout) :: mx
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    if (allocated(mx%plane)) then
      if (size(mx%plane, 2) /= mx%nslot) deallocate(mx%plane)
    end if
    if (.not. allocated(mx%plane)) then
      allocate(mx%plane(4, mx%nslot), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'mixed_forget_planes', error_no_memory('the interface planes'))
        return
      end if
    end if
    mx%plane = 0.0_wp
  end subroutine mixed_forget_planes

  !> For the time step: gain(c) of every mixed cell c, the largest ratio over
  !> its materials of the material's relative volume change to the cell's,
  !> for the dt-dependent part of the closure's volume change (module
  !> header): share_m / max(f_m, vf_floor), share_m = (1 - relax) f_m +
  !> relax (f_m/B_m) / sum_k (f_k/B_k), B = rho c^2 now. A material below the
  !> volume fraction vf_floor counts as if it had vf_floor: its change is
  !> measured against that part of the cell (a sliver's collapse is left to
  !> the closure's cap rather than cutting everyone's step by 1/f_m). The
  !> gain is >= 1 for the softest material when vf_floor <= its fraction;
  !> pure cells are not touched (theirs is 1).
  subroutine mixed_volume_gain(mx, relax, vf_floor, gain)
    type(mixed_t), intent(in) :: mx
    real(wp), intent(in) :: relax, vf_floor
    real(wp), intent(inout) :: gain(:)
    integer, parameter :: maxmat = 16
    integer :: k, s, s0, s1, i, nm
    real(wp) :: bmax, sw, b(maxmat), g

    if (mx%n == 0) return
    !$omp parallel do default(none) shared(mx, relax, vf_floor, gain) private(k, s, s0, s1, i, nm, bmax, sw, b, g) &
    !$omp schedule(static)
    do k = 1, mx%n
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      nm = s1 - s0 + 1
      bmax = 0.0_wp
      do s = s0, s1
        bmax = max(bmax, mx%rho(s)*mx%cs(s)**2)
      end do
      sw = 0.0_wp
      do i = 1, nm
        s = s0 + i - 1
        ! the floors of mixed_split
        b(i) = max(mx%rho(s)*mx%cs(s)**2, 1.0e-12_wp*bmax, tiny(1.0_wp))
        sw = sw + mx%vf(s)/b(i)
      end do
      g = 1.0_wp
      do i = 1, nm
        s = s0 + i - 1
        g = max(g, ((1.0_wp - relax)*mx%vf(s) + relax*(mx%vf(s)/b(i))/sw)/max(mx%vf(s), vf_floor))
      end do
      gain(mx%cell(k)) = g
    end do
    !$omp end parallel do
  end subroutine mixed_volume_gain

  !> Keeps the material state at the start of a step (vol: cell volumes).
  subroutine mixed_save_step_start(mx, vol)
    type(mixed_t), intent(inout) :: mx
    real(wp), intent(in) :: vol(:)
    integer :: k, s
    if (mx%n == 0) return
    !$omp parallel do default(none) shared(mx, vol) private(k, s) schedule(static)
    do k = 1, mx%n
      mx%voln(k) = vol(mx%cell(k))
      do s = mx%start(k), mx%start(k + 1) - 1
        mx%vfn(s) = mx%vf(s)
        mx%en(s) = mx%e(s)
        mx%pn(s) = mx%p(s)
        mx%bn(s) = mx%rho(s)*mx%cs(s)**2
      end do
    end do
    !$omp end parallel do
  end subroutine mixed_save_step_start

  !> Shares each mixed cell's volume and energy change since the start of the
  !> step among its materials (Tipton closure, see the module header), given
  !> the new cell volumes `vol` and the cell mass and specific energy at the
  !> start (`en`) and now (`e`) from the compatible update.
  subroutine mixed_split(mx, mass, vol, area, en, e, relax, acoustic, dt, dv_cap, pfloor)
    type(mixed_t), intent(inout) :: mx
    real(wp), intent(in) :: mass(:), vol(:), area(:), en(:), e(:)
    real(wp), intent(in) :: relax, acoustic, dt, dv_cap
    !> pressure floor of each material (its p_min; none: absent, or below
    !> -huge/2): a material whose pressure was at its floor at the step's
    !> start (cavitated) has B = 0 in the closure
    real(wp), intent(in), optional :: pfloor(:)
    integer, parameter :: maxmat = 16
    integer :: k, s, c, s0, s1, nm, i
    real(wp) :: v0, dv, de, sw, pbar, theta, vm(maxmat), bm(maxmat), d(maxmat), dvm(maxmat), &
                dem(maxmat), rest, bmax, ptil, eta, bt(maxmat), vfl
    real(wp), allocatable :: floors(:)
    logical :: atfloor(maxmat), free

    if (mx%n == 0) return
    floors = [real(wp) ::]
    if (present(pfloor)) floors = pfloor
    !$omp parallel do default(none) shared(mx, mass, vol, area, en, e, relax, acoustic, dt, dv_cap, floors) &
    !$omp private(k, s, c, s0, s1, nm, i, v0, dv, de, sw, pbar, theta, vm, bm, d, dvm, dem, rest, bmax, ptil, eta, bt) &
    !$omp private(vfl, atfloor, free) schedule(static)
    do k = 1, mx%n
      c = mx%cell(k)
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      nm = s1 - s0 + 1
      v0 = mx%voln(k)
      dv = vol(c) - v0
      de = mass(c)*(e(c) - en(c))
      bmax = maxval(mx%bn(s0:s1))
      ! a cell turned inside out (the step's volume check reports it) or
      ! whose materials have no stiffness left (rho c^2 below sqrt(tiny), a
      ! broken or vanishing state, where the weights v/B would overflow):
      ! each material keeps its fraction and takes its mass share of the work
      if (.not. (v0 > 0.0_wp .and. vol(c) > 0.0_wp .and. bmax > sqrt(tiny(1.0_wp)) .and. &
                 bmax <= huge(1.0_wp))) then
        if (.not. (v0 > 0.0_wp .and. vol(c) > 0.0_wp)) cycle
        do i = 1, nm
          s = s0 + i - 1
          mx%e(s) = mx%en(s) + de/mass(c)
          mx%rho(s) = mx%mass(s)/(mx%vf(s)*vol(c))
        end do
        cycle
      end if
      sw = 0.0_wp
      pbar = 0.0_wp
      ! the acoustic resistance rho c L / dt of each material, L = acoustic
      ! times its share of the cell's thickness V/A (A: the cell's largest
      ! median-surface area)
      eta = 0.0_wp
      if (acoustic > 0.0_wp .and. dt > 0.0_wp .and. area(c) > 0.0_wp) eta = acoustic*(v0/area(c))/dt
      vfl = 0.0_wp
      do i = 1, nm
        s = s0 + i - 1
        vm(i) = mx%vfn(s)*v0
        atfloor(i) = .false.
        if (mx%mat(s) <= size(floors)) atfloor(i) = floors(mx%mat(s)) > -0.5_wp*huge(1.0_wp) .and. &
                                                  mx%pn(s) <= floors(mx%mat(s))
        if (atfloor(i)) vfl = vfl + vm(i)
        ! an infinitely compressible material (B = 0) takes the change
        bm(i) = max(mx%bn(s), 1.0e-12_wp*bmax, tiny(1.0_wp))
        bt(i) = bm(i)
        if (eta > 0.0_wp .and. vm(i) > 0.0_wp) bt(i) = bm(i) + eta*mx%vfn(s)*sqrt(mx%bn(s)*mx%mass(s)/vm(i))
        sw = sw + vm(i)/bt(i)
        pbar = pbar + (vm(i)/bt(i))*mx%pn(s)
      end do
      pbar = (pbar - dv)/sw
      theta = relax
      free = .false.
      do i = 1, nm
        s = s0 + i - 1
        d(i) = (vm(i)/bt(i))*(mx%pn(s) - bt(i)*dv/v0 - pbar)
      end do
      if (vfl > 0.0_wp .and. any(.not. atfloor(1:nm))) &
        call cavitated(vm(1:nm), bt(1:nm), mx%pn(s0:s1), atfloor(1:nm), v0, dv, free, d(1:nm), bm(1:nm))
      do i = 1, nm
        ! no material may lose more than 90 % of its volume in one step, nor
        ! be compressed by the exchange by more than dv_cap of it (its
        ! pressure, linearised about the step's start, is only valid for
        ! small strains): its change stays above min(f dV, 0) - dv_cap V_m
        if (d(i) < 0.0_wp .and. 0.9_wp*vm(i) + (vm(i)/v0)*dv + theta*d(i) < 0.0_wp) &
          theta = max(0.0_wp, -(0.9_wp*vm(i) + (vm(i)/v0)*dv)/d(i))
        if (d(i) < 0.0_wp .and. (vm(i)/v0)*dv + theta*d(i) < min((vm(i)/v0)*dv, 0.0_wp) - dv_cap*vm(i)) &
          theta = (min((vm(i)/v0)*dv, 0.0_wp) - dv_cap*vm(i) - (vm(i)/v0)*dv)/d(i)
      end do
      do i = 1, nm
        dvm(i) = (vm(i)/v0)*dv + theta*d(i)
      end do
      if (eta > 0.0_wp .or. free) &
        call no_tension(mx%pn(s0:s1), vm(1:nm), bm(1:nm), bt(1:nm), free .and. atfloor(1:nm), dvm(1:nm))
      rest = de
      do i = 1, nm
        s = s0 + i - 1
        ! work of the material's linearised pressure at mid-step
        ptil = mx%pn(s)
        if (vm(i) > 0.0_wp) ptil = mx%pn(s) - 0.5_wp*bm(i)*dvm(i)/vm(i)
        dem(i) = -ptil*dvm(i)
        rest = rest - dem(i)
      end do
      do i = 1, nm
        s = s0 + i - 1
        dem(i) = dem(i) + rest*mx%mass(s)/mass(c)
        mx%e(s) = mx%en(s) + dem(i)/mx%mass(s)
        mx%vf(s) = (vm(i) + dvm(i))/vol(c)
        mx%rho(s) = mx%mass(s)/(mx%vf(s)*vol(c))
      end do
    end do
    !$omp end parallel do
  end subroutine mixed_split

  !> A cavitated material (at its floor) gives no resistance to growth:
  !> taken with B = 0 (the limit of the weights V/B, exactly), the common
  !> pressure is the floor's, the others relax to it and the cavitated ones
  !> take the rest of the change by volume (`free` then true). That holds
  !> only if they grow: under compression a cavitated material is as stiff
  !> as its EOS says (the cut-off model's cavities are only its elastic
  !> stretch below the floor), and the stiff exchange d stays. With one
  !> floor pressure the two agree on the sign of the cavitated materials'
  !> change, (V/B)/S (dV - sum_others (V/B)(p - p_floor)) in the stiff one,
  !> so the choice is continuous. vm: the materials' volumes in a cell of
  !> volume v0 changing by dv; bt their weights' stiffnesses, p their
  !> pressures.
  pure subroutine cavitated(vm, bt, p, floor, v0, dv, free, d, bm)
    real(wp), intent(in) :: vm(:), bt(:), p(:), v0, dv
    logical, intent(in) :: floor(:)
    logical, intent(out) :: free
    real(wp), intent(inout) :: d(:), bm(:)
    real(wp) :: vfl, pf, df(size(vm))
    vfl = sum(vm, mask=floor)
    pf = sum(vm*p, mask=floor)/vfl
    df = 0.0_wp
    where (.not. floor) df = (vm/bt)*(p - bt*dv/v0 - pf)
    free = vfl*dv/v0 - sum(df) >= 0.0_wp
    if (.not. free) return
    where (floor)
      d = -sum(df)*vm/vfl
      bm = 0.0_wp
    elsewhere
      d = df
    end where
  end subroutine cavitated

  !> An expanding material's linearised pressure p - B dV/V is kept above
  !> min(p, 0): where a share dv(i) would take it below, the material takes
  !> the expansion that brings it there and the rest goes to the others: to
  !> the cavitated ones (`floor`, B = 0) by volume where there are any, else
  !> by the weights v/bt (a lower common pressure), until no share passes its
  !> floor; where every material is at its floor the rest is shared by
  !> volume. With the acoustic resistance a gas beside a dense product has
  !> by far the larger weight and would otherwise take all of an expanding
  !> cell's growth at a negative pressure (the cell expands because the
  !> product pushes its faces out); beside cavitated water a gas relaxes to
  !> the water's floor, which may be a tension.
  pure subroutine no_tension(p, v, b, bt, floor, dv)
    real(wp), intent(in) :: p(:), v(:), b(:), bt(:)
    logical, intent(in) :: floor(:)
    real(wp), intent(inout) :: dv(:)
    logical :: held(size(dv))
    real(wp) :: excess, cap, w
    integer :: i, pass
    held = .false.
    do pass = 1, size(dv)
      excess = 0.0_wp
      do i = 1, size(dv)
        if (held(i) .or. floor(i)) cycle
        cap = v(i)*(p(i) - min(p(i), 0.0_wp))/b(i)
        if (dv(i) > cap) then
          excess = excess + dv(i) - cap
          dv(i) = cap
          held(i) = .true.
        end if
      end do
      if (.not. excess > 0.0_wp) return
      if (any(floor)) then
        w = sum(v, mask=floor)
        where (floor) dv = dv + excess*v/w
        return
      end if
      w = sum(v/bt, mask=.not. held)
      if (w > 0.0_wp) then
        where (.not. held) dv = dv + excess*(v/bt)/w
      else
        dv = dv + excess*v/sum(v)
        return
      end if
    end do
  end subroutine no_tension

  !> Cell pressure (volume-fraction weighted) and sound speed (the largest
  !> of its materials', for the time step) of every mixed cell.
  subroutine mixed_cell_state(mx, p, cs)
    type(mixed_t), intent(in) :: mx
    real(wp), intent(inout) :: p(:), cs(:)
    integer :: k, s, c
    if (mx%n == 0) return
    !$omp parallel do default(none) shared(mx, p, cs) private(k, s, c) schedule(static)
    do k = 1, mx%n
      c = mx%cell(k)
      p(c) = 0.0_wp
      cs(c) = 0.0_wp
      do s = mx%start(k), mx%start(k + 1) - 1
        p(c) = p(c) + mx%vf(s)*mx%p(s)
        cs(c) = max(cs(c), mx%cs(s))
      end do
    end do
    !$omp end parallel do
  end subroutine mixed_cell_state

  !> Registers the mixed cells' restart fields. They are always registered,
  !> as zero-size arrays when there are none, with their sizes as the scalars
  !> mixed_n and mixed_nslot: a restart file then holds its own mixed-cell
  !> sizes, which may differ from those the deck builds (after a remap).
  !> Register again after the storage is reallocated.
  subroutine mixed_register_restart(mx, reg)
    type(mixed_t), intent(inout), target :: mx
    type(registry_t), intent(inout) :: reg
    call reg%add('mixed_n', '1', mx%n, lower=LOWER_NONNEGATIVE)
    call reg%add('mixed_nslot', '1', mx%nslot, lower=LOWER_NONNEGATIVE)
    call reg%add('mixed_cell', '1', LOC_MIXED_CELL, mx%cell)
    call reg%add('mixed_start', '1', LOC_MIXED_CELL, mx%start)
    call reg%add('mixed_material', '1', LOC_MIXED_SLOT, mx%mat)
    call reg%add('mixed_volume_fraction', '1', LOC_MIXED_SLOT, mx%vf, lower=LOWER_POSITIVE)
    call reg%add('mixed_mass', 'mass', LOC_MIXED_SLOT, mx%mass, lower=LOWER_POSITIVE)
    call reg%add('mixed_energy', 'energy/mass', LOC_MIXED_SLOT, mx%e)
    call reg%add('mixed_density', 'mass/length^3', LOC_MIXED_SLOT, mx%rho, lower=LOWER_POSITIVE)
    call reg%add('mixed_pressure', 'pressure', LOC_MIXED_SLOT, mx%p)
    call reg%add('mixed_sound_speed', 'length/time', LOC_MIXED_SLOT, mx%cs, lower=LOWER_NONNEGATIVE)
    call reg%add('mixed_centroid', 'natural coordinates', LOC_MIXED_SLOT, mx%xi)
    call reg%add('mixed_plane', 'natural coordinates', LOC_MIXED_SLOT, mx%plane)
  end subroutine mixed_register_restart
end module material_mixed
