!> Builds the scene of a deck: grid, materials and their EOS, the initial
!> state from the regions (volume fractions and mixed cells where regions
!> cut cells), energy sources, nodal masses (Eq. 16) and boundaries.
module driver_scene
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t
  use base_random, only: rng_seed, rng_uniform
  use eos_factory, only: eos_create
  use mesh_grid, only: grid_init_box
  use mesh_geometry, only: hex_volume, hex_trilinear
  use mesh_boundary, only: bc_init, bc_constrain
  use material_table, only: material_index_cells, material_eval_eos
  use material_mixed, only: mixed_allocate, mixed_cell_state
  use lagrange_state, only: hydro_allocate, hydro_subcell_masses
  use io_input, only: region_cfg_t
  use io_log, only: log_line
  use driver_state, only: run, fatal, totals
  implicit none
  private
  public :: build_scene

contains

  !> Grid, materials, initial state from the regions, energy sources, nodal
  !> masses (first term of Eq. 16) and boundary lists.
  subroutine build_scene()
    type(error_t), allocatable :: err
    integer :: m, c, n, a, r, s, ijk(3)
    real(wp) :: xn(3, 8), h(3), rv

    associate (cfg => run%cfg, g => run%g, hy => run%h)
      call grid_init_box(g, cfg%ni, cfg%nj, cfg%nk, cfg%xmin, cfg%xmax, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call hydro_allocate(hy, g%ncell, g%nnode, err)
      if (allocated(err)) call fatal(err%where, err%msg)

      allocate(run%mats(size(cfg%materials)))
      do m = 1, size(cfg%materials)
        run%mats(m)%name = trim(cfg%materials(m)%name)
        call eos_create(cfg%materials(m)%eos, cfg%materials(m)%par, run%mats(m)%eos, err)
        if (allocated(err)) call fatal('&material '//run%mats(m)%name, err%msg)
        run%mats(m)%p_min = cfg%materials(m)%p_min
        run%mats(m)%rho_min = cfg%materials(m)%rho_min
      end do

      do c = 1, g%ncell
        call g%gather(c, g%x, xn)
        hy%vol(c) = hex_volume(xn)
      end do
      call fill_regions()
      do n = 1, g%nnode
        do r = 1, size(cfg%regions)
          if (inside(cfg%regions(r), g%x(:, n))) hy%u(:, n) = cfg%regions(r)%velocity
        end do
      end do
      call rng_seed(run%rng, cfg%seed)
      if (cfg%velocity_noise > 0.0_wp) then
        do n = 1, g%nnode
          do a = 1, 3
            rv = rng_uniform(run%rng)
            hy%u(a, n) = hy%u(a, n) + cfg%velocity_noise*(2.0_wp*rv - 1.0_wp)
          end do
        end do
      end if
      ! energy sources: added to the cell that contains the point
      h = (cfg%xmax - cfg%xmin)/real([cfg%ni, cfg%nj, cfg%nk], wp)
      do s = 1, size(cfg%sources)
        ijk = int((cfg%sources(s)%position - cfg%xmin)/h) + 1
        ijk = max(1, min([cfg%ni, cfg%nj, cfg%nk], ijk))
        c = ijk(1) + cfg%ni*((ijk(2) - 1) + cfg%nj*(ijk(3) - 1))
        hy%e(c) = hy%e(c) + cfg%sources(s)%energy/hy%mass(c)
        if (hy%mat(c) < 0) then
          ! a mixed cell: every material gets the same specific energy
          associate (k => -hy%mat(c))
            run%mx%e(run%mx%start(k):run%mx%start(k + 1) - 1) = &
              run%mx%e(run%mx%start(k):run%mx%start(k + 1) - 1) + cfg%sources(s)%energy/hy%mass(c)
          end associate
        end if
        call log_line('source '//itoa(s)//': energy '//rtoa(cfg%sources(s)%energy)// &
                      ' deposited in cell '//itoa(c))
      end do

      call hydro_subcell_masses(g, g%x, hy%rho, hy%mnode)

      call material_index_cells(run%mats, hy%mat, run%mx, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call material_eval_eos(run%mats, hy%rho, hy%e, hy%p, hy%cs, run%mx)
      call mixed_cell_state(run%mx, hy%p, hy%cs)

      run%bc%kind = cfg%bc_kind
      run%bc%velocity = cfg%bc_velocity
      run%bc%pressure = cfg%bc_pressure
      do m = 1, 6
        if (cfg%bc_inflow_mat(m) == 0) cycle
        run%bc%inflow_mat(m) = cfg%bc_inflow_mat(m)
        run%bc%inflow_rho(m) = cfg%bc_inflow_density(m)
        run%bc%inflow_e(m) = run%mats(cfg%bc_inflow_mat(m))%eos%energy(cfg%bc_inflow_density(m), &
                                                                      cfg%bc_inflow_pressure(m))
      end do
      call bc_init(run%bc, g, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      ! the boundary conditions hold from t = 0
      call bc_constrain(run%bc, hy%u)
    end associate
    call totals(run%tot)
    run%tot%energy_initial = run%tot%internal + run%tot%kinetic
    run%ready = .true.
    call log_line('grid: '//itoa(run%g%ni)//' x '//itoa(run%g%nj)//' x '//itoa(run%g%nk)// &
                  ' cells, '//itoa(run%g%nnode)//' nodes, '//itoa(size(run%mats))//' material(s)')
  end subroutine build_scene

  !> Fills the cells from the regions (applied in deck order, a later one
  !> overriding an earlier one). A cell whose corners and centre all lie in
  !> the same region takes that region's state; any other cell is sampled at
  !> subsamples^3 points (midpoints of a uniform split of its natural
  !> coordinates: exact volume weights on the initial box grid) and gets
  !> volume fractions, masses, energies and centroids per material. A cell
  !> with one material is pure (with the mass-averaged state of its regions);
  !> a cell with several is a mixed cell.
  subroutine fill_regions()
    type(error_t), allocatable :: err
    integer :: nmat, c, m, k, nmix, nslot, s, nm, r_only
    real(wp), allocatable :: vfm(:), massm(:), enm(:), xim(:, :), e_reg(:)
    logical :: covered

    associate (cfg => run%cfg, g => run%g, hy => run%h)
      nmat = size(cfg%materials)
      allocate(vfm(nmat), massm(nmat), enm(nmat), xim(3, nmat), e_reg(size(cfg%regions)))
      do k = 1, size(cfg%regions)
        associate (rg => cfg%regions(k))
          if (rg%energy >= 0.0_wp) then
            e_reg(k) = rg%energy
          else
            e_reg(k) = run%mats(rg%imat)%eos%energy(rg%density, rg%pressure)
          end if
        end associate
      end do
      ! pass 1: pure cells get their state, mixed cells are counted
      nmix = 0
      nslot = 0
      do c = 1, g%ncell
        call sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
        if (.not. covered) call fatal('build_scene', 'cell '//itoa(c)// &
          ' is not covered by any &region; add a region with shape = ''all'' first')
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
      ! pass 2: the mixed cells' slots
      call mixed_allocate(run%mx, nmix, nslot, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      k = 0
      s = 0
      do c = 1, g%ncell
        if (hy%mat(c) > 0) cycle
        k = k + 1
        call sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
        run%mx%cell(k) = c
        do m = 1, nmat
          if (.not. (vfm(m) > 0.0_wp)) cycle
          s = s + 1
          run%mx%mat(s) = m
          run%mx%vf(s) = vfm(m)
          run%mx%mass(s) = massm(m)
          run%mx%e(s) = enm(m)/massm(m)
          run%mx%rho(s) = massm(m)/(vfm(m)*hy%vol(c))
          run%mx%xi(:, s) = xim(:, m)/vfm(m)
        end do
        run%mx%start(k + 1) = s + 1
        hy%mass(c) = sum(massm)
        hy%rho(c) = hy%mass(c)/hy%vol(c)
        hy%e(c) = sum(enm)/hy%mass(c)
      end do
      if (nmix > 0) call log_line('mixed cells: '//itoa(nmix)//' ('//itoa(nslot)//' material slots)')
    end associate
  end subroutine fill_regions

  !> Volume fraction, mass, internal energy and centroid (natural
  !> coordinates, times the volume fraction) of each material in cell c;
  !> r_only is the region that holds the whole cell, if one does (else 0).
  subroutine sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
    integer, intent(in) :: c
    real(wp), intent(in) :: e_reg(:)
    real(wp), intent(out) :: vfm(:), massm(:), enm(:), xim(:, :)
    logical, intent(out) :: covered
    integer, intent(out) :: r_only
    real(wp) :: xn(3, 8), xi(3), w
    integer :: a, i, j, k, r, r0, ns
    logical :: same

    associate (cfg => run%cfg, g => run%g)
      call g%gather(c, g%x, xn)
      vfm = 0.0_wp; massm = 0.0_wp; enm = 0.0_wp; xim = 0.0_wp
      ! quick test: corners and centre in one region
      r0 = region_at(sum(xn, 2)/8.0_wp)
      same = .true.
      do a = 1, 8
        same = same .and. region_at(xn(:, a)) == r0
      end do
      r_only = 0
      if (same) then
        covered = (r0 > 0)
        if (.not. covered) return
        call add_sample(r0, [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp)
        r_only = r0
        return
      end if
      ns = cfg%subsamples
      w = 1.0_wp/real(ns, wp)**3
      covered = .true.
      do k = 1, ns
        do j = 1, ns
          do i = 1, ns
            xi = -1.0_wp + (2.0_wp*real([i, j, k], wp) - 1.0_wp)/real(ns, wp)
            r = region_at(hex_trilinear(xn, xi))
            if (r == 0) then
              covered = .false.
              return
            end if
            call add_sample(r, xi, w)
          end do
        end do
      end do
    end associate

  contains

    subroutine add_sample(r, xi_pt, wt)
      integer, intent(in) :: r
      real(wp), intent(in) :: xi_pt(3), wt
      integer :: m
      m = run%cfg%regions(r)%imat
      vfm(m) = vfm(m) + wt
      massm(m) = massm(m) + wt*run%cfg%regions(r)%density*run%h%vol(c)
      enm(m) = enm(m) + wt*run%cfg%regions(r)%density*e_reg(r)*run%h%vol(c)
      xim(:, m) = xim(:, m) + wt*xi_pt
    end subroutine add_sample
  end subroutine sample_cell

  !> The last region (in deck order) that contains point p, or 0.
  integer function region_at(p)
    real(wp), intent(in) :: p(3)
    integer :: r
    region_at = 0
    do r = size(run%cfg%regions), 1, -1
      if (inside(run%cfg%regions(r), p)) then
        region_at = r
        return
      end if
    end do
  end function region_at

  !> True if point p lies in the region's shape.
  pure logical function inside(rg, p)
    use io_input, only: region_cfg_t
    type(region_cfg_t), intent(in) :: rg
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
