!> Builds the scene of a deck: grid, materials and their EOS, the initial
!> state from the regions (volume fractions and mixed cells where regions
!> cut cells), energy sources, nodal masses (Eq. 16) and boundaries.
module driver_scene
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t, error_set, ERR_INPUT
  use base_random, only: rng_seed, rng_uniform
  use eos_factory, only: eos_create
  use mesh_grid, only: grid_t, grid_init_box, grid_init_nodes
  use mesh_geometry, only: hex_volume, hex_trilinear, hex_jacobian, hex_natural_unclamped, cross
  use io_grid_file, only: grid_file_read
  use io_gauges, only: gauge_locate
  use mesh_boundary, only: bc_init, bc_constrain
  use material_table, only: material_index_cells, material_eval_eos
  use material_mixed, only: mixed_allocate, mixed_cell_state
  use lagrange_state, only: hydro_allocate, hydro_subcell_masses
  use io_log, only: log_t, log_line
  use driver_scene_config, only: region_config_t
  use driver_config, only: config_t
  use driver_state, only: state_t, state_totals
  implicit none
  private
  public :: build_scene

  !> What follows a deck mistake found while building the scene (an input
  !> error's `where` is the summary line of the refusal).
  character(len=*), parameter :: deck_problem = 'the deck has 1 problem(s); nothing was run'

contains

  !> Grid, materials, initial state from the regions, energy sources, nodal
  !> masses (first term of Eq. 16) and boundary lists.
  subroutine build_scene(cfg, st, log, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, c, n, a, r, s, ijk(3), stat
    real(wp) :: xn(3, 8), h(3), rv, xi(3)
    real(wp), allocatable :: xfile(:, :)
    character(len=200) :: msg

    associate (gc => cfg%grid, g => st%g, hy => st%h, mx => st%mx)
      if (len_trim(gc%file) == 0) then
        call grid_init_box(g, gc%ni, gc%nj, gc%nk, gc%xmin, gc%xmax, err)
      else
        ! (the deck reader checked the file; read again, it is checked again)
        call grid_file_read(gc%file_path, gc%ni, gc%nj, gc%nk, xfile, err)
        if (allocated(err)) then
          call error_set(err, deck_problem, '&grid: '//err%msg, ERR_INPUT)
          return
        end if
        call grid_init_nodes(g, gc%ni, gc%nj, gc%nk, xfile, err)
        deallocate(xfile)
        call log_line(log, 'grid: node positions from '//gc%file_path)
      end if
      if (allocated(err)) return
      call hydro_allocate(hy, g%ncell, g%nnode, err)
      if (allocated(err)) return

      allocate(st%mats(size(cfg%materials)), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'build_scene', 'cannot allocate the materials: '//trim(msg))
        return
      end if
      do m = 1, size(cfg%materials)
        st%mats(m)%name = trim(cfg%materials(m)%name)
        call eos_create(cfg%materials(m)%eos, cfg%materials(m)%par, st%mats(m)%eos, err)
        if (allocated(err)) then
          call error_set(err, deck_problem, '&material '//st%mats(m)%name//': '//err%msg, ERR_INPUT)
          return
        end if
        st%mats(m)%p_min = cfg%materials(m)%p_min
        st%mats(m)%rho_min = cfg%materials(m)%rho_min
      end do

      do c = 1, g%ncell
        call g%gather(c, g%x, xn)
        hy%vol(c) = hex_volume(xn)
      end do
      call fill_regions(cfg, st, log, err)
      if (allocated(err)) return
      ! a node takes the velocity field of the last region that contains it
      do n = 1, g%nnode
        r = region_at(cfg%regions, g%x(:, n))
        if (r > 0) hy%u(:, n) = region_velocity(cfg%regions(r), g%x(:, n))
      end do
      call rng_seed(st%rng, cfg%control%seed)
      if (cfg%control%velocity_noise > 0.0_wp) then
        do n = 1, g%nnode
          do a = 1, 3
            rv = rng_uniform(st%rng)
            hy%u(a, n) = hy%u(a, n) + cfg%control%velocity_noise*(2.0_wp*rv - 1.0_wp)
          end do
        end do
      end if
      ! energy sources: added to the cell that contains the point (on a box
      ! grid the cell of index int((p - xmin)/h) + 1, a point on a face going
      ! to the cell above it; on a grid from a file, the cell found by the
      ! gauges' search, which must contain the point)
      h = (gc%xmax - gc%xmin)/real([gc%ni, gc%nj, gc%nk], wp)
      do s = 1, size(cfg%sources)
        if (len_trim(gc%file) == 0) then
          ijk = int((cfg%sources(s)%position - gc%xmin)/h) + 1
          ijk = max(1, min([gc%ni, gc%nj, gc%nk], ijk))
          c = g%cell(ijk(1), ijk(2), ijk(3))
        else
          call gauge_locate(g, cfg%sources(s)%position, 1, c, xi)
          call g%gather(c, g%x, xn)
          xi = hex_natural_unclamped(xn, cfg%sources(s)%position)
          if (.not. (maxval(abs(xi)) <= 1.0_wp + 1.0e-10_wp)) then
            call error_set(err, deck_problem, '&source('//itoa(s)//'): position is not inside the grid of '// &
                           'file '''//trim(gc%file)//'''', ERR_INPUT)
            return
          end if
        end if
        hy%e(c) = hy%e(c) + cfg%sources(s)%energy/hy%mass(c)
        if (hy%mat(c) < 0) then
          ! a mixed cell: every material gets the same specific energy
          associate (k => -hy%mat(c))
            mx%e(mx%start(k):mx%start(k + 1) - 1) = &
              mx%e(mx%start(k):mx%start(k + 1) - 1) + cfg%sources(s)%energy/hy%mass(c)
          end associate
        end if
        call log_line(log, 'source '//itoa(s)//': energy '//rtoa(cfg%sources(s)%energy)// &
                      ' deposited in cell '//itoa(c))
      end do

      call hydro_subcell_masses(g, g%x, hy%rho, hy%mnode, hy%mcorner)

      call material_index_cells(st%mats, hy%mat, mx, err)
      if (allocated(err)) return
      call material_eval_eos(st%mats, hy%rho, hy%e, hy%p, hy%cs, mx)
      call mixed_cell_state(mx, hy%p, hy%cs)

      associate (bc => st%bc, bcc => cfg%boundary)
        bc%kind = bcc%kind
        bc%velocity = bcc%velocity
        bc%pressure = bcc%pressure
        do m = 1, 6
          if (bcc%inflow_mat(m) == 0) cycle
          bc%inflow_mat(m) = bcc%inflow_mat(m)
          bc%inflow_rho(m) = bcc%inflow_density(m)
          bc%inflow_e(m) = st%mats(bcc%inflow_mat(m))%eos%energy(bcc%inflow_density(m), bcc%inflow_pressure(m))
        end do
        call bc_init(bc, g, err)
        if (allocated(err)) return
        ! the boundary conditions hold from t = 0
        call bc_constrain(bc, hy%u)
      end associate
    end associate
    call state_totals(st)
    st%tot%energy_initial = st%tot%internal + st%tot%kinetic
    st%ready = .true.
    call log_line(log, 'grid: '//itoa(st%g%ni)//' x '//itoa(st%g%nj)//' x '//itoa(st%g%nk)// &
                  ' cells, '//itoa(st%g%nnode)//' nodes, '//itoa(size(st%mats))//' material(s)')
  end subroutine build_scene

  !> Fills the cells from the regions (applied in deck order, a later one
  !> overriding an earlier one). A cell whose corners and centre all lie in
  !> the same region takes that region's state; any other cell is sampled at
  !> subsamples^3 points (midpoints of a uniform split of its natural
  !> coordinates, each weighted by the volume it stands for: the Jacobian of
  !> the trilinear map there, equal weights in a parallelepiped such as a cell
  !> of a box grid) and gets volume fractions, masses, energies and centroids
  !> per material. A cell with one material is pure (with the mass-averaged
  !> state of its regions); a cell with several is a mixed cell.
  subroutine fill_regions(cfg, st, log, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: nmat, c, m, k, nmix, nslot, s, nm, r_only
    real(wp), allocatable :: vfm(:), massm(:), enm(:), xim(:, :), e_reg(:)
    logical :: covered
    logical, allocatable :: used(:)
    character(len=200) :: msg

    associate (g => st%g, hy => st%h, mx => st%mx)
      nmat = size(cfg%materials)
      allocate(vfm(nmat), massm(nmat), enm(nmat), xim(3, nmat), e_reg(size(cfg%regions)), &
               used(size(cfg%regions)), stat=k, errmsg=msg)
      if (k /= 0) then
        call error_set(err, 'fill_regions', 'cannot allocate work arrays: '//trim(msg))
        return
      end if
      used = .false.
      do k = 1, size(cfg%regions)
        associate (rg => cfg%regions(k))
          if (rg%energy >= 0.0_wp) then
            e_reg(k) = rg%energy
          else
            e_reg(k) = st%mats(rg%imat)%eos%energy(rg%density, rg%pressure)
          end if
        end associate
      end do
      ! pass 1: pure cells get their state, mixed cells are counted
      nmix = 0
      nslot = 0
      do c = 1, g%ncell
        call sample_cell(cfg, g, hy%vol(c), c, e_reg, vfm, massm, enm, xim, covered, r_only, used)
        if (.not. covered) then
          call error_set(err, deck_problem, 'cell '//itoa(c)// &
            ' is not covered by any &region; add a region with shape = ''all'' first', ERR_INPUT)
          return
        end if
        nm = count(vfm > 0.0_wp)
        if (nm == 1) then
          m = maxloc(vfm, 1)
          hy%mat(c) = m
          if (r_only > 0) then
            ! the whole cell in one region: its state exactly as given
            hy%rho(c) = cfg%regions(r_only)%density
            hy%e(c) = e_reg(r_only)
            hy%mass(c) = hy%rho(c)*hy%vol(c)
          else
            hy%mass(c) = massm(m)
            hy%rho(c) = massm(m)/hy%vol(c)
            hy%e(c) = enm(m)/massm(m)
          end if
        else
          nmix = nmix + 1
          nslot = nslot + nm
          hy%mat(c) = -nmix
        end if
      end do
      ! a region that gives no cell any material is most likely a mistake
      ! (outside the box, or hidden by later regions): say so
      do k = 1, size(cfg%regions)
        if (.not. used(k)) call log_line(log, 'WARNING: &region('//itoa(k)//') ('//trim(cfg%regions(k)%shape)// &
          ') fills no part of any cell: it lies outside the grid, is smaller than the sampling, or later '// &
          'regions cover it')
      end do
      ! pass 2: the mixed cells' slots
      call mixed_allocate(mx, nmix, nslot, err)
      if (allocated(err)) return
      k = 0
      s = 0
      do c = 1, g%ncell
        if (hy%mat(c) > 0) cycle
        k = k + 1
        call sample_cell(cfg, g, hy%vol(c), c, e_reg, vfm, massm, enm, xim, covered, r_only, used)
        mx%cell(k) = c
        do m = 1, nmat
          if (.not. (vfm(m) > 0.0_wp)) cycle
          s = s + 1
          mx%mat(s) = m
          mx%vf(s) = vfm(m)
          mx%mass(s) = massm(m)
          mx%e(s) = enm(m)/massm(m)
          mx%rho(s) = massm(m)/(vfm(m)*hy%vol(c))
          mx%xi(:, s) = xim(:, m)/vfm(m)
        end do
        mx%start(k + 1) = s + 1
        hy%mass(c) = sum(massm)
        hy%rho(c) = hy%mass(c)/hy%vol(c)
        hy%e(c) = sum(enm)/hy%mass(c)
      end do
      if (nmix > 0) call log_line(log, 'mixed cells: '//itoa(nmix)//' ('//itoa(nslot)//' material slots)')
    end associate
  end subroutine fill_regions

  !> Volume fraction, mass, internal energy and centroid (natural
  !> coordinates, times the volume fraction) of each material in cell c;
  !> r_only is the region that holds the whole cell, if one does (else 0).
  subroutine sample_cell(cfg, g, vol, c, e_reg, vfm, massm, enm, xim, covered, r_only, used)
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: vol
    integer, intent(in) :: c
    real(wp), intent(in) :: e_reg(:)
    real(wp), intent(out) :: vfm(:), massm(:), enm(:), xim(:, :)
    logical, intent(out) :: covered
    integer, intent(out) :: r_only
    logical, intent(inout) :: used(:)
    real(wp) :: xn(3, 8), xi(3), w, jmin, jmax, jsum
    integer :: a, i, j, k, r, r0, ns
    logical :: same, affine

    call g%gather(c, g%x, xn)
    vfm = 0.0_wp; massm = 0.0_wp; enm = 0.0_wp; xim = 0.0_wp
    ! quick test: corners and centre in one region
    r0 = region_at(cfg%regions, sum(xn, 2)/8.0_wp)
    same = .true.
    do a = 1, 8
      same = same .and. region_at(cfg%regions, xn(:, a)) == r0
    end do
    r_only = 0
    if (same) then
      covered = (r0 > 0)
      if (.not. covered) return
      call add_sample(r0, [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp)
      r_only = r0
      return
    end if
    ns = cfg%grid%subsamples
    ! A sample stands for the volume det J(xi) dxi around it. In a
    ! parallelepiped det J is constant and the weights are equal (kept exactly
    ! 1/ns^3, so that box grids fill as they always did); otherwise each is
    ! det J over the sum of them (a folded corner, det J < 0, counts 0).
    jmin = huge(1.0_wp)
    jmax = -huge(1.0_wp)
    jsum = 0.0_wp
    do k = 1, ns
      do j = 1, ns
        do i = 1, ns
          w = hex_jacobian(xn, sample_xi(i, j, k))
          jmin = min(jmin, w)
          jmax = max(jmax, w)
          jsum = jsum + max(w, 0.0_wp)
        end do
      end do
    end do
    affine = jmax - jmin <= 1.0e-12_wp*abs(jmax) .or. .not. (jsum > 0.0_wp)
    w = 1.0_wp/real(ns, wp)**3
    covered = .true.
    do k = 1, ns
      do j = 1, ns
        do i = 1, ns
          xi = sample_xi(i, j, k)
          r = region_at(cfg%regions, hex_trilinear(xn, xi))
          if (r == 0) then
            covered = .false.
            return
          end if
          if (.not. affine) w = max(hex_jacobian(xn, xi), 0.0_wp)/jsum
          call add_sample(r, xi, w)
        end do
      end do
    end do

  contains

    !> Natural coordinates of sample (i,j,k): the midpoints of a uniform
    !> split of [-1,1]^3 into ns^3 parts.
    pure function sample_xi(i, j, k) result(x)
      integer, intent(in) :: i, j, k
      real(wp) :: x(3)
      x = -1.0_wp + (2.0_wp*real([i, j, k], wp) - 1.0_wp)/real(ns, wp)
    end function sample_xi

    subroutine add_sample(r, xi_pt, wt)
      integer, intent(in) :: r
      real(wp), intent(in) :: xi_pt(3), wt
      integer :: m
      m = cfg%regions(r)%imat
      used(r) = .true.
      vfm(m) = vfm(m) + wt
      massm(m) = massm(m) + wt*cfg%regions(r)%density*vol
      enm(m) = enm(m) + wt*cfg%regions(r)%density*e_reg(r)*vol
      xim(:, m) = xim(:, m) + wt*xi_pt
    end subroutine add_sample
  end subroutine sample_cell

  !> The last region (in deck order) that contains point p, or 0.
  pure integer function region_at(regions, p)
    type(region_config_t), intent(in) :: regions(:)
    real(wp), intent(in) :: p(3)
    integer :: r
    region_at = 0
    do r = size(regions), 1, -1
      if (inside(regions(r), p)) then
        region_at = r
        return
      end if
    end do
  end function region_at

  !> The initial velocity a region gives a node at p (length/time):
  !> 'uniform' its velocity; 'radial' velocity + speed (p - center)/|p - center|
  !> (just velocity at the centre itself; speed < 0 points inward, as in
  !> Noh's problem); 'rotation' velocity + angular_velocity a x (p - center),
  !> a rigid rotation about the region's axis a through center.
  pure function region_velocity(rg, p) result(u)
    type(region_config_t), intent(in) :: rg
    real(wp), intent(in) :: p(3)
    real(wp) :: u(3), d(3), r, a(3)
    u = rg%velocity
    d = p - rg%center
    select case (trim(rg%velocity_field))
    case ('radial')
      ! (sqrt of a sum of squares, not norm2: exact under scaling by powers of two)
      r = sqrt(dot_product(d, d))
      if (r > 0.0_wp) u = u + rg%speed*(d/r)
    case ('rotation')
      a = 0.0_wp
      a(rg%axis) = 1.0_wp
      u = u + rg%angular_velocity*cross(a, d)
    end select
  end function region_velocity

  !> True if point p lies in the region's shape.
  pure logical function inside(rg, p)
    type(region_config_t), intent(in) :: rg
    real(wp), intent(in) :: p(3)
    real(wp) :: d(3)
    select case (trim(rg%shape))
    case ('all')
      inside = .true.
    case ('box')
      inside = all(p >= rg%lo) .and. all(p <= rg%hi)
    case ('sphere')
      inside = sum((p - rg%center)**2) <= rg%radius**2
    case ('half_space')
      inside = dot_product(p - rg%center, rg%normal) >= 0.0_wp
    case ('cylinder')
      d = p - rg%center
      d(rg%axis) = 0.0_wp
      inside = sum(d**2) <= rg%radius**2 .and. p(rg%axis) >= rg%lo(rg%axis) .and. &
               p(rg%axis) <= rg%hi(rg%axis)
    case default
      inside = .false.
    end select
  end function inside
end module driver_scene
