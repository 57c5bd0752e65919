!> The 1D spherical pre-run (&prerun): the deck's charge and what surrounds
!> it (its `all` region and the sphere regions about one centre) run in one
!> dimension (`spherical_lagrange`) to the mapping time, then mapped into
!> the grid's cells and nodes within the mapped radius (in the manner of
!> AUTODYN's 1D-to-3D remap and LS-DYNA's *INITIAL_ALE_MAPPING); the 3D run
!> starts at that time.
!>
!> The mapping is conservative: each 1D zone's overlaps with the cells
!> (`spherical_map`, approximate) are rescaled over the whole grid (exact
!> sums over the blocks, `base_xsum`) to the zone's volume within the grid,
!> f (r_k^3 - r_{k-1}^3) 4 pi/3 (f = 1/2 for each symmetry plane through the
!> centre), so the cells receive exactly the zone's mass, radial momentum and
!> total energy times f. A node's velocity is radial, its radial momentum the
!> shares of its cells' (`prerun_nodes`); each cell's internal energy is its
!> mapped total energy less the kinetic energy of its corners, so the total
!> energy is that of the 1D run.
module driver_prerun
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_no_memory, error_t, error_set, ERR_INPUT, ERR_RUNTIME
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_grid, only: grid_t
  use mesh_grid_config, only: grid_axis_nodes
  use mesh_halo, only: halo_t
  use mesh_boundary, only: BC_SYMMETRY, BC_WALL
  use material_table, only: material_t, material_index_cells
  use material_mixed, only: mixed_t, mixed_allocate
  use spherical_lagrange, only: sphere_t, sphere_setup, sphere_dt, sphere_step, sphere_energy, sphere_merge, &
                                sphere_refresh
  use spherical_map, only: sphere_box_overlaps
  use io_log, only: log_t, log_line
  use io_blast, only: blast_t, blast_answers
  use io_gauges, only: gauges_t, gauges_write_given
  use driver_config, only: config_t
  use driver_burn, only: burn_state, deck_problem
  implicit none
  private
  public :: prerun_t, prerun_gauge_rows, prerun_run, prerun_plan, prerun_scale, prerun_cell, prerun_nodes, &
            prerun_write, prerun_report, prerun_totals

  real(wp), parameter :: pi = 3.14159265358979323846_wp

  !> The 1D run at the mapping time and how it maps.
  type :: prerun_t
    type(sphere_t) :: s
    real(wp) :: centre(3) = 0.0_wp
    real(wp) :: fdom = 1.0_wp              !< the part of a sphere about the centre inside the grid
    integer :: kmap = 0                    !< zones 1..kmap are mapped (r(kmap): the mapped radius)
    integer :: kshock = 0                  !< the outermost zone the run disturbed
    integer :: nsub = 8
    real(wp), allocatable :: scale(:)      !< (kmap) each zone's overlaps' factor (`prerun_scale`)
    real(wp), allocatable :: ov(:), mom(:, :)   !< (kmap) overlaps of one cell (work)
    real(wp), allocatable :: prad(:)       !< (ncell) radial momentum each cell got
    logical, allocatable :: hit(:)         !< (ncell) the cell got some of the 1D run
    logical, allocatable :: in1d(:)        !< (regions) the regions the 1D run took
    real(wp), allocatable :: grad(:)       !< (gauges) the &output gauges' distances from the centre
    real(wp), allocatable :: gt(:), gv(:, :, :)   !< 1D gauge rows: times; density, pressure, energy,
                                               !< sound speed, radial velocity (5, gauge, row)
    integer :: nrow = 0
  end type prerun_t

contains

  !> Sets up the 1D run from the deck (mats: the scene's materials, with
  !> their EOS) and runs it to &prerun time, logging its progress; refuses a
  !> deck it cannot represent and a run that is not done by then.
  subroutine prerun_run(cfg, mats, log, pr, err)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mats(:)
    type(log_t), intent(in) :: log
    type(prerun_t), intent(out) :: pr
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: bk(:), p0(:)
    real(wp) :: c(3), r1d, dz, rc, x(3), e0, ei, ek, dt, tnext, t_map, rho0, dv, v_cj, dt_row, trow, rfar, rgeo, wfar
    integer :: k, j, n, z, nz, stat, m, tries, lastsph, ng, nm, nmerged
    logical :: ok, burns
    character(len=200) :: msg

    associate (pc => cfg%pre1d, s => pr%s)
      t_map = pc%time
      if (len_trim(cfg%grid%file) > 0) then
        call refuse('&prerun maps onto a box grid, uniform or graded (&grid without file), for now')
        return
      end if
      ! the centre: the deck's, else the last sphere region's
      lastsph = 0
      do k = 1, size(cfg%regions)
        if (cfg%regions(k)%shape == 'sphere') lastsph = k
      end do
      if (pc%center(1) < 0.5_wp*huge(1.0_wp)) then
        c = pc%center
      else if (lastsph > 0) then
        c = cfg%regions(lastsph)%center
      else
        call refuse('&prerun: no sphere region (the charge) and no center')
        return
      end if
      pr%centre = c
      ! the domain: to the grid box's farthest corner unless given
      r1d = pc%radius
      if (.not. r1d > 0.0_wp) then
        do k = 0, 7
          x = merge(cfg%grid%xmax, cfg%grid%xmin, [btest(k, 0), btest(k, 1), btest(k, 2)])
          r1d = max(r1d, sqrt(dot_product(x - c, x - c)))
        end do
      end if
      ! the regions the 1D run takes: shape all, and spheres about c at rest
      bk = [r1d]
      dz = huge(1.0_wp)
      do k = 1, size(cfg%regions)
        associate (rg => cfg%regions(k))
          if (.not. one_d(k)) cycle
          if (any(abs(rg%velocity) > 0.0_wp) .or. (rg%velocity_field == 'radial' .and. abs(rg%speed) > 0.0_wp) .or. &
              (rg%velocity_field == 'rotation' .and. abs(rg%angular_velocity) > 0.0_wp)) then
            call refuse('&prerun: &region('//itoa(k)//') moves; the 1D run starts at rest')
            return
          end if
          if (rg%shape /= 'sphere') cycle
          if (rg%radius < r1d) bk = [bk, rg%radius]
          if (rg%inner_radius > 0.0_wp) bk = [bk, rg%inner_radius]
          dz = min(dz, rg%radius/100.0_wp)
        end associate
      end do
      if (pc%zone_width > 0.0_wp) dz = pc%zone_width
      if (.not. dz < huge(1.0_wp)) dz = r1d/1000.0_wp
      ! node radii: uniform between the interfaces (which fall on nodes), and
      ! beyond the outermost sphere growing in proportion to the radius (the
      ! ratio of the zone width to that sphere's radius: the blast wave
      ! broadens as it runs out), up to far_zone_width
      call sort_unique(bk)
      ! (the growing zones end where they reach far_zone_width (default ten
      ! times zone_width), at radius rfar; uniform zones of about that
      ! width beyond: a blast wave's peak is eroded over a few zones, and
      ! zones that keep growing with the radius lose it further out, 1 kg
      ! TNT at 3 m: 67.2 kPa with 30 mm zones there, 74.1 with 5.3 mm)
      wfar = pc%far_zone_width
      if (.not. wfar > 0.0_wp) wfar = 10.0_wp*dz
      rfar = huge(1.0_wp)
      if (size(bk) > 1) rfar = max(bk(size(bk) - 1), wfar*bk(size(bk) - 1)/dz)
      nz = 0
      do j = 1, size(bk)
        nz = nz + zones_in(j)
      end do
      if (nz > 20000000) then
        call refuse('&prerun: '//itoa(nz)//' zones (radius '//rtoa(r1d)//' / zone_width '//rtoa(dz)// &
                    '); give a larger zone_width')
        return
      end if
      s%nz = nz
      allocate(s%r(0:nz), s%u(0:nz), s%mn(0:nz), s%m(nz), s%rho(nz), s%e(nz), s%p(nz), s%cs(nz), s%q(nz), &
               s%mat(nz), p0(nz), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'prerun_run', error_no_memory('the 1D run'))
        return
      end if
      s%r(0) = 0.0_wp
      z = 0
      do j = 1, size(bk)
        rc = merge(0.0_wp, bk(max(j - 1, 1)), j == 1)
        n = zones_in(j)
        if (j == size(bk) .and. j > 1) then
          ng = geometric_zones(j)
          rgeo = min(bk(j), rfar)
          do k = 1, ng
            s%r(z + k) = rc*(rgeo/rc)**(real(k, wp)/real(ng, wp))
          end do
          do k = ng + 1, n
            s%r(z + k) = rgeo + (bk(j) - rgeo)*real(k - ng, wp)/real(n - ng, wp)
          end do
        else
          do k = 1, n
            s%r(z + k) = rc + (bk(j) - rc)*real(k, wp)/real(n, wp)
          end do
        end if
        s%r(z + n) = bk(j)
        z = z + n
      end do
      s%u = 0.0_wp
      ! each zone: the last region (deck order) holding its centre
      do z = 1, nz
        rc = 0.5_wp*(s%r(z - 1) + s%r(z))
        m = 0
        do k = 1, size(cfg%regions)
          associate (rg => cfg%regions(k))
            if (.not. one_d(k)) cycle
            if (rg%shape == 'sphere' .and. .not. (rc < rg%radius .and. rc > rg%inner_radius)) cycle
            m = k
          end associate
        end do
        if (m == 0) then
          call refuse('&prerun: the zone at radius '//rtoa(rc)//' is in no region (give a region with shape = ''all'')')
          return
        end if
        associate (rg => cfg%regions(m))
          s%mat(z) = rg%imat
          s%rho(z) = rg%density
          if (rg%energy >= 0.0_wp) then
            s%e(z) = rg%energy
          else
            s%e(z) = mats(rg%imat)%eos%energy(rg%density, rg%pressure)
          end if
        end associate
      end do
      allocate(s%mats(size(mats)), source=mats, stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'prerun_run', error_no_memory('the 1D run'))
        return
      end if
      call mixed_allocate(s%mx, 0, 0, err)
      if (.not. allocated(err)) call material_index_cells(s%mats, s%mat, s%mx, err)
      if (allocated(err)) return
      ! programmed burn: lit at the centre
      burns = .false.
      do m = 1, size(mats)
        if (.not. any(cfg%detonations%imat == m)) cycle
        if (.not. any(s%mat == m)) cycle
        do k = 1, size(cfg%detonations)
          associate (dk => cfg%detonations(k))
            if (dk%imat /= m) cycle
            if (dk%shape /= 'point' .or. sqrt(dot_product(dk%point - c, dk%point - c)) > 1.0e-6_wp*dz) then
              call refuse('&prerun: &detonation('//itoa(k)//') is not a point at the centre '//vtext(c)// &
                          '; a 1D run lights its charge there')
              return
            end if
          end associate
        end do
        if (.not. burn_state(cfg, mats(m), m, log, rho0, dv, v_cj, err)) cycle
        if (allocated(err)) return
        k = findloc(cfg%detonations%imat, m, dim=1)
        allocate(s%mats(m)%burn, stat=stat, errmsg=msg)
        if (stat == 0) allocate(s%mats(m)%burn%light(nz), s%mats(m)%burn%tau(nz), s%mats(m)%burn%f(nz), &
                                stat=stat, errmsg=msg)
        if (stat /= 0) then
          call error_set(err, 'prerun_run', error_no_memory('the 1D run''s lighting times'))
          return
        end if
        associate (b => s%mats(m)%burn)
          b%rho0 = rho0
          b%v_cj = v_cj
          b%light = huge(1.0_wp)
          b%tau = 1.0_wp
          do z = 1, nz
            if (s%mat(z) /= m) cycle
            b%light(z) = cfg%detonations(k)%time + 0.5_wp*(s%r(z - 1) + s%r(z))/dv
            b%tau(z) = cfg%materials(m)%burn_width*(s%r(z) - s%r(z - 1))/dv
            if (b%light(z) + b%tau(z) > t_map) then
              call refuse('&prerun: time = '//rtoa(t_map)//' is before &material '''//mats(m)%name// &
                          ''' has burnt (its zone at radius '//rtoa(s%r(z))//' burns until '// &
                          rtoa(b%light(z) + b%tau(z))//'); map later')
              return
            end if
          end do
        end associate
        burns = .true.
      end do
      s%q_lin = pc%q_linear
      s%q_quad = pc%q_quad
      s%cfl = pc%cfl
      s%t = 0.0_wp
      call sphere_setup(s)
      p0 = s%p
      call sphere_energy(s, ei, ek)
      e0 = ei + ek
      call log_line(log, 'prerun: 1D spherical run about '//vtext(c)//': '//itoa(nz)//' zones to radius '// &
                    rtoa(r1d)//' (zone width '//rtoa(dz)//'), to t = '//rtoa(t_map)// &
                    trim(merge(' (programmed burn)      ', ' (constant-volume start)', burns)))
      ! the 1D gauges: the deck's gauges at their distances from the centre,
      ! a row each gauge_dt (or each 1/20000 of the time)
      pr%grad = [(sqrt(dot_product(cfg%output%gauges(:, k) - c, cfg%output%gauges(:, k) - c)), &
                  k = 1, cfg%output%ngauge)]
      allocate(pr%gt(1024), pr%gv(5, size(pr%grad), 1024), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'prerun_run', error_no_memory('the 1D gauges'))
        return
      end if
      dt_row = cfg%output%gauge_dt
      if (.not. dt_row > 0.0_wp) dt_row = t_map/20000.0_wp
      trow = 0.0_wp
      if (size(pr%grad) > 0) call gauge_row(pr)
      ! the run, with its progress in tenths of the time
      tnext = 0.1_wp*t_map
      nmerged = 0
      do while (s%t < t_map*(1.0_wp - 1.0e-12_wp))
        dt = min(sphere_dt(s), t_map - s%t)
        if (s%steps > 0) dt = min(dt, 1.5_wp*s%dt)
        tries = 0
        do
          call sphere_step(s, dt, ok)
          if (ok) exit
          tries = tries + 1
          dt = 0.5_wp*dt
          if (tries > 20) then
            call error_set(err, 'prerun_run', 'the 1D run''s zones turned inside out at t = '//rtoa(s%t), ERR_RUNTIME)
            return
          end if
        end do
        ! thin hot zones merged (`sphere_merge`), the materials' cell lists
        ! and the zones' pressures then taken again
        if (pc%merge_ratio > 0.0_wp) then
          call sphere_merge(s, pc%merge_ratio, p0, nm, stat)
          if (stat /= 0) then
            call error_set(err, 'prerun_run', error_no_memory('the 1D run''s merged zones'))
            return
          end if
          if (nm > 0) then
            nmerged = nmerged + nm
            call material_index_cells(s%mats, s%mat, s%mx, err)
            if (allocated(err)) return
            call sphere_refresh(s)
          end if
        end if
        if (s%steps >= 50000000) then
          call error_set(err, 'prerun_run', 'the 1D run took 5e7 steps and is at t = '//rtoa(s%t)//' of '// &
                         rtoa(t_map), ERR_RUNTIME)
          return
        end if
        if (size(pr%grad) > 0 .and. (s%t >= trow + dt_row .or. .not. s%t < t_map*(1.0_wp - 1.0e-12_wp))) then
          call gauge_row(pr)
          trow = s%t
        end if
        if (s%t >= tnext .or. .not. s%t < t_map*(1.0_wp - 1.0e-12_wp)) then
          call disturbed(pr, p0)
          call log_line(log, 'prerun: t = '//rtoa(s%t)//', step '//itoa(s%steps)//', dt '//rtoa(s%dt)// &
                        ', disturbed to r = '//rtoa(s%r(pr%kshock)))
          tnext = tnext + 0.1_wp*t_map
        end if
      end do
      call sphere_energy(s, ei, ek)
      call log_line(log, 'prerun: total energy '//rtoa(4.0_wp*pi*e0)//' at t = 0, '//rtoa(4.0_wp*pi*(ei + ek))// &
                    ' at t = '//rtoa(s%t)//' (relative change '//rtoa((ei + ek - e0)/e0)//'); '//itoa(s%steps)// &
                    ' steps, '//itoa(nmerged)//' zone merges ('//itoa(s%nz)//' zones left)')
      call disturbed(pr, p0)
      if (pr%kshock >= s%nz - 1) then
        call refuse('&prerun: the 1D run''s wave reached its outer radius '//rtoa(r1d)//' by t = '//rtoa(t_map)// &
                    '; give a larger radius or map earlier')
        return
      end if
      pr%in1d = [(one_d(k), k = 1, size(cfg%regions))]
    end associate

  contains

    !> The zones between interfaces bk(j-1) and bk(j) (`prerun_run`).
    integer function zones_in(j) result(n)
      integer, intent(in) :: j
      if (j == 1) then
        n = max(1, ceiling(bk(1)/dz - 1.0e-9_wp))
      else if (j == size(bk)) then
        n = geometric_zones(j)
        if (rfar < bk(j)) n = n + max(1, ceiling((bk(j) - rfar)/wfar - 1.0e-9_wp))
      else
        n = max(1, ceiling((bk(j) - bk(j - 1))/dz - 1.0e-9_wp))
      end if
    end function zones_in

    !> The zones of the last interval (j) that grow in proportion to the
    !> radius: from bk(j - 1) to bk(j), or to rfar where it is nearer.
    integer function geometric_zones(j) result(n)
      integer, intent(in) :: j
      n = 0
      if (rfar > bk(j - 1)) &
        n = max(1, ceiling(log10(min(bk(j), rfar)/bk(j - 1))/log10(1.0_wp + dz/bk(j - 1)) - 1.0e-9_wp))
    end function geometric_zones

    !> Region k is one the 1D run takes (shape all, or a sphere about c).
    logical function one_d(k)
      integer, intent(in) :: k
      associate (rg => cfg%regions(k))
        one_d = rg%shape == 'all' .or. (rg%shape == 'sphere' .and. &
          sqrt(dot_product(rg%center - c, rg%center - c)) <= 1.0e-9_wp*max(rg%radius, tiny(1.0_wp)))
      end associate
    end function one_d

    subroutine refuse(text)
      character(len=*), intent(in) :: text
      call error_set(err, deck_problem, text, ERR_INPUT)
    end subroutine refuse
  end subroutine prerun_run

  !> How the 1D run maps into the grid: the mapped radius (beyond the
  !> disturbance by two cells, or the deck's, on a node), the part of each
  !> sphere in the grid (a half per symmetry plane through the centre; the
  !> sphere must not cross another face).
  subroutine prerun_plan(cfg, log, pr, err)
    type(config_t), intent(in) :: cfg
    type(log_t), intent(in) :: log
    type(prerun_t), intent(inout) :: pr
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: h(3), rmap
    real(wp), allocatable :: xa(:)
    integer :: a, j, n, stat
    character(len=200) :: msg
    associate (s => pr%s, pc => cfg%pre1d, c => pr%centre)
      h = (cfg%grid%xmax - cfg%grid%xmin)/real([cfg%grid%ni, cfg%grid%nj, cfg%grid%nk], wp)
      if (cfg%grid%graded()) then
        ! (a graded box: the widest cell along each axis within the
        ! disturbance's reach of the centre)
        do a = 1, 3
          xa = grid_axis_nodes(cfg%grid, a)
          n = size(xa) - 1
          h(a) = maxval(xa(2:) - xa(:n), mask=xa(2:) >= c(a) - s%r(pr%kshock) .and. xa(:n) <= c(a) + s%r(pr%kshock))
        end do
      end if
      rmap = s%r(pr%kshock) + 2.0_wp*maxval(h)
      if (pc%map_radius > 0.0_wp) then
        if (pc%map_radius < s%r(pr%kshock)) then
          call refuse('&prerun: map_radius = '//rtoa(pc%map_radius)//' is inside the 1D run''s disturbance (to '// &
                      'r = '//rtoa(s%r(pr%kshock))//'); what lies beyond it would be lost')
          return
        end if
        rmap = pc%map_radius
      end if
      pr%kmap = findloc(s%r(1:) >= rmap*(1.0_wp - 1.0e-12_wp), .true., dim=1)
      if (pr%kmap == 0 .or. pr%kmap >= s%nz) then
        call refuse('&prerun: the mapped radius '//rtoa(rmap)//' is beyond the 1D run''s radius '//rtoa(s%r(s%nz)))
        return
      end if
      rmap = s%r(pr%kmap)
      pr%fdom = 1.0_wp
      do a = 1, 3
        do j = 0, 1
          associate (face => merge(cfg%grid%xmax(a), cfg%grid%xmin(a), j == 1), f => 2*a - 1 + j)
            if (abs(c(a) - face) <= 1.0e-9_wp*rmap) then
              if (cfg%boundary%kind(f) /= BC_SYMMETRY .and. cfg%boundary%kind(f) /= BC_WALL) then
                call refuse('&prerun: the centre lies on a grid face whose &boundary is not a symmetry plane')
                return
              end if
              pr%fdom = 0.5_wp*pr%fdom
            else if ((j == 0 .and. c(a) - rmap < face) .or. (j == 1 .and. c(a) + rmap > face)) then
              call refuse('&prerun: the mapped sphere (radius '//rtoa(rmap)//' about '//vtext(c)// &
                          ') crosses a face of the grid; map earlier or give a larger grid')
              return
            end if
          end associate
        end do
      end do
      call log_line(log, 'prerun: disturbed to r = '//rtoa(s%r(pr%kshock))//'; mapped within r = '//rtoa(rmap)// &
                    ' ('//itoa(pr%kmap)//' zones, '//rtoa(pr%fdom)//' of each sphere in the grid)')
      pr%nsub = pc%subsamples
      allocate(pr%scale(pr%kmap), pr%ov(pr%kmap), pr%mom(3, pr%kmap), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'prerun_plan', error_no_memory('the mapping'))
        return
      end if
      pr%ov = 0.0_wp
      pr%mom = 0.0_wp
    end associate

  contains

    subroutine refuse(text)
      character(len=*), intent(in) :: text
      call error_set(err, deck_problem, text, ERR_INPUT)
    end subroutine refuse
  end subroutine prerun_plan

  !> A row of the 1D gauges at the run's time: density, pressure, energy,
  !> sound speed and radial velocity at each gauge's radius, linear between
  !> the zone centres around it (the velocity between the nodes).
  subroutine gauge_row(pr)
    type(prerun_t), intent(inout) :: pr
    real(wp), allocatable :: t(:), v(:, :, :)
    real(wp) :: r, ra, rb, w
    integer :: g, z, zn, lo, hi, mid, stat
    associate (s => pr%s)
      if (pr%nrow == size(pr%gt)) then
        allocate(t(2*pr%nrow), v(5, size(pr%grad), 2*pr%nrow), stat=stat)
        if (stat /= 0) return   ! (the rows stop growing: the answers come from those kept)
        t(1:pr%nrow) = pr%gt
        v(:, :, 1:pr%nrow) = pr%gv
        call move_alloc(t, pr%gt)
        call move_alloc(v, pr%gv)
      end if
      pr%nrow = pr%nrow + 1
      pr%gt(pr%nrow) = s%t
      do g = 1, size(pr%grad)
        r = pr%grad(g)
        ! the zone z whose centre is the last at or below r (bisection)
        lo = 1
        hi = s%nz
        do while (lo < hi)
          mid = (lo + hi + 1)/2
          if (0.5_wp*(s%r(mid - 1) + s%r(mid)) <= r) then
            lo = mid
          else
            hi = mid - 1
          end if
        end do
        z = lo
        zn = min(z + 1, s%nz)
        ra = 0.5_wp*(s%r(z - 1) + s%r(z))
        rb = 0.5_wp*(s%r(zn - 1) + s%r(zn))
        w = 0.0_wp
        if (rb > ra) w = min(1.0_wp, max(0.0_wp, (r - ra)/(rb - ra)))
        pr%gv(1:4, g, pr%nrow) = (1.0_wp - w)*[s%rho(z), s%p(z), s%e(z), s%cs(z)] + &
                                 w*[s%rho(zn), s%p(zn), s%e(zn), s%cs(zn)]
        ! (the node velocities: the node at or below r and the next)
        z = min(s%nz - 1, max(0, findloc(s%r >= r, .true., dim=1) - 2))
        w = min(1.0_wp, max(0.0_wp, (r - s%r(z))/(s%r(z + 1) - s%r(z))))
        pr%gv(5, g, pr%nrow) = (1.0_wp - w)*s%u(z) + w*s%u(z + 1)
      end do
    end associate
  end subroutine gauge_row

  !> The 1D gauge rows before the mapping time as rows of the run's gauge
  !> file (its points are the gauges the 1D rows were taken at, in order):
  !> a gauge's history then starts at t = 0, and the blast answers at the end
  !> of the run take the part the shock passed in the 1D run from it.
  subroutine prerun_gauge_rows(pr, points, gs)
    type(prerun_t), intent(in) :: pr
    real(wp), intent(in) :: points(:, :)
    type(gauges_t), intent(in) :: gs
    real(wp) :: vals(7, size(pr%grad)), d(3)
    integer :: k, g
    do k = 1, pr%nrow
      if (.not. pr%gt(k) < pr%s%t*(1.0_wp - 1.0e-12_wp)) exit
      do g = 1, size(pr%grad)
        d = points(:, g) - pr%centre
        if (pr%grad(g) > 0.0_wp) d = d/pr%grad(g)
        vals(:, g) = [pr%gv(1:4, g, k), pr%gv(5, g, k)*d]
      end do
      call gauges_write_given(gs, pr%gt(k), vals)
    end do
  end subroutine prerun_gauge_rows

  !> kshock: the outermost zone whose pressure differs from its initial p0
  !> by more than 1e-6 of it (a zone at rest gets round-off differences in
  !> its density from its radii).
  pure subroutine disturbed(pr, p0)
    type(prerun_t), intent(inout) :: pr
    real(wp), intent(in) :: p0(:)
    integer :: z
    associate (s => pr%s)
      pr%kshock = 1
      do z = s%nz, 1, -1
        if (abs(s%p(z) - p0(z)) > 1.0e-6_wp*abs(p0(z))) then
          pr%kshock = z
          return
        end if
      end do
    end associate
  end subroutine disturbed

  !> Each mapped zone's factor from its overlaps with the owned cells of all
  !> blocks (exact sums) to its volume in the grid; refuses a zone no cell
  !> overlaps (too few subsamples for the zone width).
  subroutine prerun_scale(pr, g, halo, err)
    type(prerun_t), intent(inout) :: pr
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    type(error_t), allocatable, intent(inout) :: err
    type(xsum_t), allocatable :: acc(:)
    real(wp) :: xn(3, 8), vin, tot
    integer :: i, j, k, z, k1, k2, stat
    character(len=200) :: msg
    allocate(acc(pr%kmap), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'prerun_scale', error_no_memory('the mapping''s sums'))
      return
    end if
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          call g%gather(g%cell(i, j, k), g%x, xn)
          call sphere_box_overlaps(xn(:, 1), xn(:, 8), pr%centre, pr%s%r, pr%kmap, pr%nsub, k1, k2, pr%ov, pr%mom, vin)
          do z = k1, k2
            call xsum_add(acc(z), pr%ov(z))
          end do
          if (k2 >= k1) then
            pr%ov(k1:k2) = 0.0_wp
            pr%mom(:, k1:k2) = 0.0_wp
          end if
        end do
      end do
    end do
    call halo%sums(acc)
    do z = 1, pr%kmap
      tot = xsum_value(acc(z))
      if (.not. tot > 0.0_wp) then
        call error_set(err, deck_problem, '&prerun: no cell overlaps the 1D zone at radius '//rtoa(pr%s%r(z))// &
                       '; give more subsamples or a wider zone_width', ERR_INPUT)
        return
      end if
      pr%scale(z) = pr%fdom*4.0_wp*pi*(pr%s%r(z)**3 - pr%s%r(z - 1)**3)/3.0_wp/tot
    end do
  end subroutine prerun_scale

  !> The 1D run's mass, total energy and radial momentum within the mapped
  !> radius, times the part of each sphere in the grid (what the mapping
  !> gives the cells).
  pure function prerun_totals(pr) result(tot)
    type(prerun_t), intent(in) :: pr
    real(wp) :: tot(3)
    integer :: z
    tot = 0.0_wp
    associate (s => pr%s)
      do z = 1, pr%kmap
        tot = tot + s%m(z)*[1.0_wp, s%e(z) + 0.25_wp*(s%u(z - 1)**2 + s%u(z)**2), 0.5_wp*(s%u(z - 1) + s%u(z))]
      end do
    end associate
    tot = 4.0_wp*pi*pr%fdom*tot
  end function prerun_totals

  !> What cell xn (an axis-aligned box, volume vol) gets of the 1D run: per
  !> material the volume vm, mass mm, total energy em (internal plus the
  !> zones' kinetic energy, `prerun_nodes` takes the nodes' out) and first
  !> moment xm about the cell's centre (vm and xm from the scaled overlaps);
  !> vin the part of the cell inside the mapped radius (the sum of its
  !> overlaps before scaling: the cell's sub-boxes inside it); prad its
  !> radial momentum.
  subroutine prerun_cell(pr, xn, vm, mm, em, xm, vin, prad)
    type(prerun_t), intent(inout) :: pr
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: vm(:), mm(:), em(:), xm(:, :), vin, prad
    integer :: k1, k2, z, m
    real(wp) :: v, mass
    vm = 0.0_wp; mm = 0.0_wp; em = 0.0_wp; xm = 0.0_wp; prad = 0.0_wp
    associate (s => pr%s)
      call sphere_box_overlaps(xn(:, 1), xn(:, 8), pr%centre, s%r, pr%kmap, pr%nsub, k1, k2, pr%ov, pr%mom, vin)
      do z = k1, k2
        m = s%mat(z)
        v = pr%ov(z)*pr%scale(z)
        mass = s%rho(z)*v
        vm(m) = vm(m) + v
        mm(m) = mm(m) + mass
        em(m) = em(m) + mass*(s%e(z) + 0.25_wp*(s%u(z - 1)**2 + s%u(z)**2))
        xm(:, m) = xm(:, m) + pr%mom(:, z)*pr%scale(z)
        prad = prad + mass*0.5_wp*(s%u(z - 1) + s%u(z))
      end do
      if (k2 >= k1) then
        pr%ov(k1:k2) = 0.0_wp
        pr%mom(:, k1:k2) = 0.0_wp
      end if
    end associate
  end subroutine prerun_cell

  !> The nodes' velocities from the cells' radial momenta pr%prad: a cell
  !> gives each corner node a share in proportion to the node's distance
  !> from the centre (the 1D velocity grows from 0 at the
  !> centre: a node there gets none, and the shares add up to the cell's
  !> momentum); a node's velocity is radial, its radial momentum the sum of
  !> its shares. Each node's kinetic energy is then taken from the internal
  !> energy of the cells that gave it momentum, in proportion to their shares
  !> (a cell ahead of the 1D run's shock, which gave none, keeps its energy;
  !> a mixed cell's materials give the same specific amount), so the total
  !> energy is what the cells were given.
  subroutine prerun_nodes(pr, g, mass, mnode, mat, mx, u, e, err)
    type(prerun_t), intent(in) :: pr
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: mass(:), mnode(:)
    integer, intent(in) :: mat(:)
    type(mixed_t), intent(inout) :: mx
    real(wp), intent(inout) :: u(:, :), e(:)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: pn(:), qn(:), q(:, :)
    real(wp) :: d(3), r(8), w(8), ke
    integer :: c, a, n, stat
    allocate(pn(g%nnode), qn(g%nnode), q(8, g%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'prerun_nodes', error_no_memory('the mapped nodes'))
      return
    end if
    pn = 0.0_wp
    qn = 0.0_wp
    q = 0.0_wp
    do c = 1, g%ncell
      if (.not. pr%hit(c)) cycle
      do a = 1, 8
        n = g%node0(c) + g%corner_offset(a)
        d = g%x(:, n) - pr%centre
        r(a) = sqrt(dot_product(d, d))
        w(a) = mass(c)*r(a)
      end do
      do a = 1, 8
        n = g%node0(c) + g%corner_offset(a)
        q(a, c) = pr%prad(c)*w(a)/sum(w)
        pn(n) = pn(n) + q(a, c)
        qn(n) = qn(n) + abs(q(a, c))
      end do
    end do
    do n = 1, g%nnode
      if (.not. qn(n) > 0.0_wp) cycle
      d = g%x(:, n) - pr%centre
      r(1) = sqrt(dot_product(d, d))
      u(:, n) = (pn(n)/mnode(n))*(d/r(1))
    end do
    do c = 1, g%ncell
      if (.not. pr%hit(c)) cycle
      ke = 0.0_wp
      do a = 1, 8
        n = g%node0(c) + g%corner_offset(a)
        if (qn(n) > 0.0_wp) ke = ke + 0.5_wp*mnode(n)*dot_product(u(:, n), u(:, n))*abs(q(a, c))/qn(n)
      end do
      e(c) = e(c) - ke/mass(c)
      if (mat(c) < 0) then
        associate (k => -mat(c))
          mx%e(mx%start(k):mx%start(k + 1) - 1) = mx%e(mx%start(k):mx%start(k + 1) - 1) - ke/mass(c)
        end associate
      end if
    end do
  end subroutine prerun_nodes

  !> The 1D run's files: `<base>_prerun.txt`, its profile at the end, a row
  !> per zone (radii, zone centre, density, mean velocity, pressure, specific
  !> internal energy, sound speed, material), and with gauges
  !> `<base>_prerun_gauges.txt` (time, then at each gauge's distance from the
  !> centre density, pressure, energy, sound speed and radial velocity:
  !> `tools/blast_gauges.py` reads it).
  subroutine prerun_write(pr, base, err)
    type(prerun_t), intent(in) :: pr
    character(len=*), intent(in) :: base
    type(error_t), allocatable, intent(inout) :: err
    integer :: u, ios, z, g, k
    character(len=200) :: msg
    open(newunit=u, file=base//'_prerun.txt', status='replace', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'prerun_write', 'cannot write '//base//'_prerun.txt: '//trim(msg))
      return
    end if
    associate (s => pr%s)
      write(u, '(a)') '# the 1D spherical pre-run at t = '//rtoa(s%t)//' ('//itoa(s%steps)//' steps), about '// &
                      vtext(pr%centre)//'; zones 1..'//itoa(pr%kmap)//' mapped'
      write(u, '(a)') '# r_in r_out r density velocity pressure energy sound_speed material'
      do z = 1, s%nz
        write(u, '(8es24.15e3,1x,a)') s%r(z - 1), s%r(z), 0.5_wp*(s%r(z - 1) + s%r(z)), s%rho(z), &
          0.5_wp*(s%u(z - 1) + s%u(z)), s%p(z), s%e(z), s%cs(z), s%mats(s%mat(z))%name
      end do
    end associate
    close(u)
    if (size(pr%grad) == 0) return
    open(newunit=u, file=base//'_prerun_gauges.txt', status='replace', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'prerun_write', 'cannot write '//base//'_prerun_gauges.txt: '//trim(msg))
      return
    end if
    write(u, '(a)') '# the 1D spherical pre-run''s gauges: the pressure at each gauge''s distance from the centre'
    do g = 1, size(pr%grad)
      write(u, '(a)') '# gauge '//itoa(g)//' at radius '//rtoa(pr%grad(g))
    end do
    write(u, '(a)') '# time'//cat([(' density_'//itoa(g)//' pressure_'//itoa(g)//' energy_'//itoa(g)// &
                                    ' sound_speed_'//itoa(g)//' velocity_'//itoa(g), g = 1, size(pr%grad))])
    do k = 1, pr%nrow
      write(u, '(*(es24.15e3))') pr%gt(k), pr%gv(:, :, k)
    end do
    close(u)

  contains

    pure function cat(parts) result(text)
      character(len=*), intent(in) :: parts(:)
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(parts)
        text = text//trim(parts(i))
      end do
    end function cat
  end subroutine prerun_write

  !> The 1D gauges' blast answers (`io_blast`), for the log.
  subroutine prerun_report(pr, log)
    type(prerun_t), intent(in) :: pr
    type(log_t), intent(in) :: log
    type(blast_t) :: b
    integer :: g
    do g = 1, size(pr%grad)
      b = blast_answers(pr%gt(1:pr%nrow), pr%gv(2, g, 1:pr%nrow))
      if (.not. b%arrived) then
        call log_line(log, 'prerun gauge '//itoa(g)//' (radius '//rtoa(pr%grad(g))//'): no overpressure by t = '// &
                      rtoa(pr%s%t))
        cycle
      end if
      call log_line(log, 'prerun gauge '//itoa(g)//' (radius '//rtoa(pr%grad(g))//'): arrival '//rtoa(b%arrival)// &
                    ', peak overpressure '//rtoa(b%peak)//', positive duration '//rtoa(b%duration)// &
                    ', positive impulse '//rtoa(b%impulse)//trim(merge('            ', ' (not ended)', b%ended)))
    end do
  end subroutine prerun_report

  !> Sorts v ascending and drops repeats.
  pure subroutine sort_unique(v)
    real(wp), allocatable, intent(inout) :: v(:)
    real(wp) :: t
    integer :: i, j, n
    do i = 2, size(v)
      t = v(i)
      j = i - 1
      do while (j >= 1)
        if (.not. v(j) > t) exit
        v(j + 1) = v(j)
        j = j - 1
      end do
      v(j + 1) = t
    end do
    n = min(1, size(v))
    do i = 2, size(v)
      if (v(i) > v(n)) then
        n = n + 1
        v(n) = v(i)
      end if
    end do
    v = v(1:n)
  end subroutine sort_unique

  function vtext(v) result(text)
    real(wp), intent(in) :: v(3)
    character(len=:), allocatable :: text
    text = '('//rtoa(v(1))//', '//rtoa(v(2))//', '//rtoa(v(3))//')'
  end function vtext
end module driver_prerun
