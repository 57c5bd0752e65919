!> Benchmark of the Euler-phase remap (not a test: it asserts nothing and is
!> run by `make bench` through tools/bench.sh, never by ctest).
!>
!> 1. A global remap of an n^3 box (default 40^3 on [0,1]^3): the old grid is
!>    the box with every node moved by up to `amp` of the spacing (seeded;
!>    interior nodes in all three directions, face and edge nodes only
!>    within their face or edge, corners fixed), the new grid is the uniform
!>    box (a rezone back to the initial grid, as `&rezone mode = 'global'`
!>    does), so every cell is remapped. Smooth density, energy and velocity.
!>    a. one material: pure cells only (remap_pure);
!>    b. the same grids and fields with two materials split by a tilted plane
!>       (the mixed cells cut exactly by `mof_cut_volume`, as in
!>       test_remap_euler's 'plane' setup; remap_two).
!>    The swept-face path is taken where no changed cell blocks it (timed
!>    with the remap), as `driver_euler` decides; pure_exact is remap_pure
!>    by intersection, for the ratio of the two paths.
!>    c. general_pure: one material, the same old grid remapped to another
!>       perturbed grid (seed + 1) instead of the box: new cells that are
!>       not boxes take the general intersection path (48 new halves
!>       clipped by the old pieces), as after a smoothing rezone (LSSM).
!>    The mixed cells are a few per cent of the grid, so T(remap_two) -
!>    T(remap_pure) is within the noise of a busy machine. Their cost is
!>    therefore measured on a band: only the nodes within `band_width`
!>    spacings of the plane move (by what they move in the global grid),
!>    so only the cells around the interface are remapped, once with one
!>    material (band_pure) and once with two (band_two). Same grids, same
!>    cells remapped: T(band_two) - T(band_pure), over the old mixed cells
!>    that moved, is what the interface costs per mixed cell (the MoF
!>    reconstructions and the extra clipping of new cells against material
!>    regions, in the mixed cells and in the new cells that overlap them);
!>    a mixed cell costs that plus a pure cell of remap_pure.
!> 2. MoF: `mof_reconstruct` on random planes (random unit normal, volume
!>    fraction uniform in [0.01, 0.99]) through unit cubes, randomly
!>    perturbed unit cubes (non-planar faces) and sheared, perturbed hexes;
!>    reconstructions per second, mean iterations, how many hit the cap.
!>
!> Rates are per second of wall time with all threads and per thread. Each
!> remap is timed reps_global (remap_*, general_pure) or reps_band (band_*)
!> times (a fresh state each time,
!> the five cases interleaved) and the fastest is kept. Usage:
!>   bench_remap [n [mof_samples [reps_global [reps_band [section]]]]]   (defaults 40 20000 2 3 all)
!> section `flat` runs only the table of the same moved cells in larger
!> grids (3.), fastest of reps_band, for profiling one part.
program bench_remap
  use base_kinds, only: wp, pi
  use base_errors, only: error_t, error_set
  use base_random, only: rng_t, rng_seed, rng_uniform
  use base_timers, only: wall_seconds
  use base_strings, only: itoa
  use base_memory, only: memory_keep_freed
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_corner, hex_volume, hex_natural
  use mesh_boundary, only: bc_t, bc_init
  use material_mixed, only: mixed_t, mixed_allocate
  use hydro_state, only: hydro_t, hydro_allocate, hydro_totals, hydro_subcell_masses
  use mesh_halo, only: halo_t
  use geometry_cells, only: cell_moments
  use geometry_mof, only: mof_cut_volume, mof_plane_for_volume, mof_reconstruct, mof_max_iter_default
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step, remap_swept_blockers, remap_work_t
  use omp_lib, only: omp_get_max_threads
  implicit none
  !> Largest node displacement of the old grid, in cell spacings.
  real(wp), parameter :: amp = 0.1_wp
  !> Seed of the old grid's perturbation and of the MoF samples.
  integer, parameter :: seed = 20240605
  !> The material interface n.x = d of the two-material case (unit n,
  !> through the box's centre, tilted against all three axes).
  real(wp), parameter :: plane_n(3) = [0.8_wp, 0.36_wp, 0.48_wp]
  real(wp), parameter :: plane_d = 0.5_wp*(0.8_wp + 0.36_wp + 0.48_wp)
  !> The band of the local runs: nodes within this many spacings of the plane.
  real(wp), parameter :: band_width = 1.0_wp
  !> The four remaps: global or band grid, one or two materials.
  integer, parameter :: ncase = 8
  character(len=12), parameter :: case_name(ncase) = [character(len=12) :: 'remap_pure', 'remap_two', &
                                                       'band_pure', 'band_two', 'general_pure', 'pure_exact', &
                                                       'lattice_pure', 'lattice_two']
  integer :: n, nmof, reps(2), nthreads, rep, k, nmix(ncase), i_mixed
  real(wp), allocatable :: xglobal(:, :), xband(:, :), xbox(:, :), xgeneral(:, :)
  real(wp) :: tbest(ncase), cbest(ncase), cons(3, ncase), change(3), t, tc, us_pure, us_extra
  type(remap_stats_t) :: stb(ncase), st
  type(grid_t) :: g0
  type(error_t), allocatable :: err
  logical :: only_flat

  call read_arguments(n, nmof, reps, only_flat)
  ! freed work arrays kept for the next remap, as runs keep them (`driver`)
  call memory_keep_freed()
  if (only_flat) then
    call bench_flat()
    stop
  end if
  nthreads = omp_get_max_threads()
  call grid_init_box(g0, n, n, n, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
  call stop_on(err)
  xbox = g0%x
  xglobal = perturbed(g0, huge(1.0_wp), seed)
  xband = perturbed(g0, band_width, seed)
  xgeneral = perturbed(g0, huge(1.0_wp), seed + 1)

  ! interleaved, so that a slow spell of the machine hits all cases alike
  tbest = huge(1.0_wp)
  do rep = 1, maxval(reps)
    do k = 1, ncase
      if (rep > merge(reps(2), reps(1), k == 3 .or. k == 4)) cycle
      select case (k)
      case (1, 2)
        call time_remap(2 - mod(k, 2), xglobal, xbox, .true., t, tc, st, change, nmix(k))
      case (3, 4)
        call time_remap(2 - mod(k, 2), xband, xbox, .true., t, tc, st, change, nmix(k))
      case (5)
        call time_remap(1, xglobal, xgeneral, .true., t, tc, st, change, nmix(k))
      case (6)
        call time_remap(1, xglobal, xbox, .false., t, tc, st, change, nmix(k))
      case (7)
        call time_remap(1, xglobal, xbox, .false., t, tc, st, change, nmix(k), lattice=.true.)
      case default
        call time_remap(2, xglobal, xbox, .true., t, tc, st, change, nmix(k), lattice=.true.)
      end select
      if (t < tbest(k)) then
        tbest(k) = t
        cbest(k) = tc
        stb(k) = st
        cons(:, k) = change
      end if
    end do
  end do

  write(*, '(a)') '== remap benchmark (tests/bench_remap.f90, this build) =='
  write(*, '(a,i0,a,i0,a)') 'grid ', n, '^3 on [0,1]^3, ', nthreads, ' threads (omp_get_max_threads); new grid: '// &
    'the uniform box (global rezone)'
  write(*, '(a,f4.2,a,i0,a)') 'old grid: nodes moved by up to ', amp, ' of the spacing (seed ', seed, &
    '; boundary nodes within their faces)'
  write(*, '(a,i0,a,i0,a)') 'fastest of ', reps(1), ' (global) and ', reps(2), ' (band) timings of each remap'
  write(*, '(a)') ''
  write(*, '(a)') 'row          count    wall[s]   per_second  per_s_thread  us_x_thread    cpu[s]'
  do k = 1, ncase
    call row(case_name(k), stb(k)%cells_remapped, tbest(k), cbest(k))
  end do
  i_mixed = stb(4)%mof_cells
  us_pure = 1.0e6_wp*tbest(1)*nthreads/max(stb(1)%cells_remapped, 1)
  us_extra = 1.0e6_wp*(tbest(4) - tbest(3))*nthreads/max(i_mixed, 1)
  call row('mixed_extra', i_mixed, tbest(4) - tbest(3), cbest(4) - cbest(3))
  write(*, '(a12,i8,11x,es12.3,es14.3,f13.1)') 'mixed_cell  ', i_mixed, &
    1.0e6_wp*nthreads/(us_pure + us_extra), 1.0e6_wp/(us_pure + us_extra), us_pure + us_extra
  write(*, '(a)') 'us_x_thread: microseconds of one thread per item (wall time x threads / count)'
  write(*, '(a)') 'cpu:         CPU time of the process, all threads; wall x threads well above it means other'
  write(*, '(a)') '             processes took the cores (then compare the cpu column; 1 thread: cpu ~ wall)'
  write(*, '(a)') 'remap_pure:  every node moved, one material: every cell remapped, all pure'
  write(*, '(a,i0,a)') 'remap_two:   the same, two materials split by a tilted plane (', nmix(2), &
    ' old mixed cells, cut exactly)'
  write(*, '(a,f3.1,a)') 'band_*:      only the nodes within ', band_width, &
    ' spacing of the plane moved (as in remap_*), one and two materials'
  write(*, '(a)') 'mixed_extra: T(band_two) - T(band_pure) over the old mixed cells that moved: same grids, same'
  write(*, '(a)') '             cells remapped, so the difference is what the interface costs (MoF, and clipping'
  write(*, '(a)') '             against material regions in the mixed cells and the new cells overlapping them)'
  write(*, '(a)') 'mixed_cell:  a pure cell (remap_pure) plus mixed_extra'
  write(*, '(a)') 'general_pure: remap_pure, but to another perturbed grid (seed + 1), not the box: the general path'
  write(*, '(a)') 'pure_exact:  remap_pure by intersection (the swept-face path off): remap_pure takes the swept faces'
  write(*, '(a)') '             where every changed cell can (remap_swept_blockers, timed with the remap), as runs do'
  write(*, '(a)') 'lattice_pure, lattice_two: pure_exact and remap_two on the lattice path (`remap_lattice`: the new'
  write(*, '(a)') '             grid is a lattice, each old half clipped once by the half-cells it reaches), as runs'
  write(*, '(a)') '             whose rezone returns to a box grid do'
  write(*, '(a,2f7.2)') 'lattice path speed-up (per-cell clipping / lattice, wall), pure and two materials:', &
    tbest(6)/tbest(7), tbest(2)/tbest(8)
  write(*, '(a)') ''
  do k = 1, ncase
    call stats_block(case_name(k), stb(k), cons(:, k))
  end do
  write(*, '(a)') ''
  call bench_flat()
  write(*, '(a)') ''
  call bench_mof()

contains

  !> Stops the benchmark with the error's message, if there is one.
  subroutine stop_on(e)
    type(error_t), allocatable, intent(in) :: e
    if (.not. allocated(e)) return
    write(*, '(a)') 'bench_remap: '//e%where//': '//e%msg
    error stop 1
  end subroutine stop_on

  !> The optional command-line arguments: grid size, MoF samples per hex
  !> kind, timings of each global and of each band remap.
  subroutine read_arguments(n_, nmof_, reps_, flat_)
    integer, intent(out) :: n_, nmof_, reps_(2)
    logical, intent(out) :: flat_
    character(len=64) :: arg
    integer :: i, v, ios, vals(4)
    vals = [40, 20000, 2, 3]
    do i = 1, min(command_argument_count(), 4)
      call get_command_argument(i, arg)
      read(arg, *, iostat=ios) v
      if (ios /= 0 .or. v < 1) then
        write(*, '(a)') 'usage: bench_remap [n [mof_samples [reps_global [reps_band]]]] (positive integers; got '// &
          trim(arg)//')'
        error stop 2
      end if
      vals(i) = v
    end do
    n_ = vals(1)
    nmof_ = vals(2)
    reps_ = vals(3:4)
    flat_ = .false.
    if (command_argument_count() >= 5) then
      call get_command_argument(5, arg)
      flat_ = arg == 'flat'
      if (.not. (flat_ .or. arg == 'all')) then
        write(*, '(a)') 'usage: bench_remap [n [mof_samples [reps_global [reps_band [all|flat]]]]] (got '// &
          trim(arg)//')'
        error stop 2
      end if
    end if
  end subroutine read_arguments

  !> The box grid g with its nodes moved by up to amp of the spacing in each
  !> direction where the node is not on the boundary (face nodes move within
  !> their face, edge nodes along their edge, corners stay), so the old grid
  !> covers exactly the same box as the new one. Only nodes within `band`
  !> spacings of the plane move; every node draws its numbers, so a band
  !> grid's moved nodes are where they are in the global grid (band huge).
  function perturbed(g, band, seed_) result(x)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: band
    integer, intent(in) :: seed_
    real(wp), allocatable :: x(:, :)
    type(rng_t) :: rng
    integer :: i, j, k, d, idx(3), nn, nd(3)
    real(wp) :: hh(3), r(3)
    logical :: inside
    x = g%x
    nd = [g%ni, g%nj, g%nk]
    hh = (g%xmax - g%xmin)/real(nd, wp)
    call rng_seed(rng, seed_)
    do k = 0, g%nk
      do j = 0, g%nj
        do i = 0, g%ni
          idx = [i, j, k]
          nn = g%node(i, j, k)
          inside = abs(dot_product(plane_n, g%x(:, nn)) - plane_d) <= band*maxval(hh)
          do d = 1, 3
            r(d) = 2.0_wp*rng_uniform(rng) - 1.0_wp
            if (inside .and. idx(d) > 0 .and. idx(d) < nd(d)) x(d, nn) = x(d, nn) + amp*hh(d)*r(d)
          end do
        end do
      end do
    end do
  end function perturbed

  !> The cost of a remap that changes the same cells in grids of 20^3, 40^3
  !> and 60^3: the nodes within 4 index steps of the centre node moved as in
  !> `perturbed`, one material, back to the box (the swept-face path, the
  !> driver's choice timed with it, and its work arrays kept from one repetition
  !> to the next as the driver keeps them); fastest of reps(2).
  subroutine bench_flat()
    integer, parameter :: sizes(3) = [20, 40, 60]
    integer :: k, rep, n_keep, nm_
    real(wp) :: t, tc, tb, cb, ch(3)
    real(wp), allocatable :: xo(:, :)
    type(grid_t) :: gb
    type(remap_stats_t) :: sb
    type(remap_work_t) :: work
    n_keep = n
    write(*, '(a)') '== the same moved cells in a larger grid (a ball of 4 index steps about the centre node, '// &
      'remapped back to the box; fastest of '//itoa(reps(2))//') =='
    write(*, '(a)') 'grid    cells  remapped    wall[s]     cpu[s]  us_per_remapped_cell(cpu)   prepare intersect '// &
      'assemble[s]'
    do k = 1, size(sizes)
      n = sizes(k)
      call grid_init_box(gb, n, n, n, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
      call stop_on(err)
      ! (allocated first: GCC takes the reallocating assignment's bounds of
      ! an unallocated array for uninitialized)
      if (allocated(xo)) deallocate(xo)
      allocate(xo(3, gb%nnode))
      xo = gb%x
      call move_ball(gb, xo)
      tb = huge(1.0_wp)
      cb = huge(1.0_wp)
      do rep = 1, reps(2)
        call time_remap(1, xo, gb%x, .true., t, tc, sb, ch, nm_, work=work)
        tb = min(tb, t)
        cb = min(cb, tc)
      end do
      write(*, '(i4,a,i8,i10,2f11.4,f14.2,3f10.4)') n, '^3', gb%ncell, sb%cells_remapped, tb, cb, &
        1.0e6_wp*cb/max(sb%cells_remapped, 1), sb%t_prepare, sb%t_intersect, sb%t_assemble
    end do
    n = n_keep
  end subroutine bench_flat

  !> The nodes of the box grid g within 4 index steps of its centre node
  !> moved by up to amp of the spacing (seeded per node by its offset from
  !> the centre, so every grid moves the same nodes alike), into x.
  subroutine move_ball(g, x)
    type(grid_t), intent(in) :: g
    real(wp), intent(inout) :: x(:, :)
    type(rng_t) :: rng
    integer :: i, j, k, off(3)
    real(wp) :: hh
    hh = 1.0_wp/real(g%ni, wp)
    do k = 0, g%nk
      do j = 0, g%nj
        do i = 0, g%ni
          off = [i, j, k] - g%ni/2
          if (sum(off**2) > 16) cycle
          call rng_seed(rng, seed + 1000*(off(1) + 10) + 100*(off(2) + 10) + off(3) + 10)
          x(1, g%node(i, j, k)) = x(1, g%node(i, j, k)) + amp*hh*(2.0_wp*rng_uniform(rng) - 1.0_wp)
          x(2, g%node(i, j, k)) = x(2, g%node(i, j, k)) + amp*hh*(2.0_wp*rng_uniform(rng) - 1.0_wp)
          x(3, g%node(i, j, k)) = x(3, g%node(i, j, k)) + amp*hh*(2.0_wp*rng_uniform(rng) - 1.0_wp)
        end do
      end do
    end do
  end subroutine move_ball

  !> Smooth density factor (dimensionless, in [0.7, 1.4]) at the point p.
  pure real(wp) function rho_field(p)
    real(wp), intent(in) :: p(3)
    rho_field = 1.0_wp + 0.2_wp*sin(2.0_wp*pi*p(1))*cos(2.0_wp*pi*p(2)) + 0.1_wp*p(3)
  end function rho_field

  !> Smooth specific internal energy at the point p.
  pure real(wp) function e_field(p)
    real(wp), intent(in) :: p(3)
    e_field = 2.0_wp + 0.5_wp*cos(pi*p(1))*sin(pi*p(3)) + 0.3_wp*p(2)
  end function e_field

  !> Smooth velocity at the point p, normal component zero on the box's
  !> faces (so the symmetry conditions take no momentum away).
  pure function u_field(p) result(u)
    real(wp), intent(in) :: p(3)
    real(wp) :: u(3)
    u = [sin(pi*p(1))*cos(pi*p(2)), 0.5_wp*sin(pi*p(2))*cos(pi*p(3)), 0.8_wp*sin(pi*p(3))*cos(pi*p(1))]
  end function u_field

  !> Builds the state on the old grid (nmat = 1: one material; 2: material 1
  !> below plane_n.x = plane_d, twice as dense, material 2 above it, half as
  !> dense, the cut cells mixed with their exact volume fractions and
  !> centroids), remaps it to xnew and returns the wall and CPU times of
  !> remap_euler_step alone (s), its statistics, the relative changes of
  !> mass, momentum and total energy, and the number of mixed cells.
  subroutine time_remap(nmat, xold, xnew, sweep, tw, tcpu, stats, change, nmix, lattice, work)
    integer, intent(in) :: nmat
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    !> the swept-face path where no cell blocks it, as the driver does (else intersection)
    logical, intent(in) :: sweep
    !> the lattice path (`remap_params_t`; absent: off)
    logical, intent(in), optional :: lattice
    !> work arrays kept from one call to the next, as the driver keeps
    !> them (`remap_work_t`; absent: the remap's own)
    type(remap_work_t), intent(inout), optional :: work
    real(wp), intent(out) :: tw, tcpu
    type(remap_stats_t), intent(out) :: stats
    real(wp), intent(out) :: change(3)
    integer, intent(out) :: nmix
    type(grid_t) :: g
    type(hydro_t) :: h
    type(mixed_t) :: mx
    type(bc_t) :: bc
    type(remap_params_t) :: par
    type(error_t), allocatable :: e
    real(wp), allocatable :: vol(:), cen(:, :)
    integer, allocatable :: moved(:)
    real(wp) :: xn(3, 8), v1, c1(3), c2(3), vcell, m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, w0, c0, pscale
    integer :: c, s, nn, stat
    character(len=200) :: msg

    call grid_init_box(g, n, n, n, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], e)
    call stop_on(e)
    g%x = xold
    call bc_init(bc, g, e)
    call stop_on(e)
    call hydro_allocate(h, g%ncell, g%nnode, e)
    call stop_on(e)
    allocate(vol(g%ncell), cen(3, g%ncell), stat=stat, errmsg=msg)
    if (stat /= 0) call error_set(e, 'time_remap', 'cannot allocate: '//trim(msg))
    call stop_on(e)
    call cell_moments(n, n, n, xold, vol, cen)
    h%mat = 1
    nmix = 0
    do c = 1, g%ncell
      call g%gather(c, xold, xn)
      h%vol(c) = vol(c)
      h%rho(c) = rho_field(cen(:, c))
      h%e(c) = e_field(cen(:, c))
      if (nmat == 2) then
        call mof_cut_volume(xn, plane_n, plane_d, v1, c1)
        if (v1 > 1.0e-12_wp*vol(c) .and. v1 < (1.0_wp - 1.0e-12_wp)*vol(c)) then
          nmix = nmix + 1
          h%mat(c) = -nmix
        else if (v1 > 0.5_wp*vol(c)) then
          h%rho(c) = 2.0_wp*h%rho(c)
        else
          h%mat(c) = 2
          h%rho(c) = 0.5_wp*h%rho(c)
          h%e(c) = h%e(c) + 2.0_wp
        end if
      end if
      h%mass(c) = h%rho(c)*vol(c)
    end do
    call mixed_allocate(mx, nmix, 2*nmix, e)
    call stop_on(e)
    nmix = 0
    do c = 1, g%ncell
      if (h%mat(c) > 0) cycle
      call g%gather(c, xold, xn)
      vcell = vol(c)
      call mof_cut_volume(xn, plane_n, plane_d, v1, c1)
      c2 = (cen(:, c)*vcell - c1*v1)/(vcell - v1)
      nmix = nmix + 1
      mx%cell(nmix) = c
      mx%start(nmix + 1) = mx%start(nmix) + 2
      s = mx%start(nmix)
      mx%mat(s:s + 1) = [1, 2]
      mx%vf(s:s + 1) = [v1/vcell, 1.0_wp - v1/vcell]
      mx%rho(s:s + 1) = [2.0_wp*rho_field(c1), 0.5_wp*rho_field(c2)]
      mx%mass(s:s + 1) = mx%rho(s:s + 1)*mx%vf(s:s + 1)*vcell
      mx%e(s:s + 1) = [e_field(c1), e_field(c2) + 2.0_wp]
      mx%p(s:s + 1) = 0.4_wp*mx%rho(s:s + 1)*mx%e(s:s + 1)
      mx%cs(s:s + 1) = 1.0_wp
      mx%xi(:, s) = hex_natural(xn, c1)
      mx%xi(:, s + 1) = hex_natural(xn, c2)
      h%mass(c) = sum(mx%mass(s:s + 1))
      h%rho(c) = h%mass(c)/vcell
      h%e(c) = dot_product(mx%mass(s:s + 1), mx%e(s:s + 1))/h%mass(c)
    end do
    h%p = 0.4_wp*h%rho*h%e
    h%cs = 1.0_wp
    call hydro_subcell_masses(g, xold, h%rho, h%mnode, h%mcorner)
    do nn = 1, g%nnode
      h%u(:, nn) = u_field(xold(:, nn))
    end do

    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    pscale = 0.0_wp
    do nn = 1, g%nnode
      pscale = pscale + h%mnode(nn)*norm2(h%u(:, nn))
    end do
    call cpu_time(c0)
    w0 = wall_seconds()
    ! (as the driver: the blockers' moved cells handed to the remap)
    if (sweep) par%swept = remap_swept_blockers(g, h, bc, xnew, par%swept_max, par%swept_mixed, moved=moved, &
                                                work=work) == 0
    if (present(lattice)) par%lattice = lattice
    call remap_euler_step(g, h, mx, nmat, bc, xnew, par, stats, e, moved=moved, work=work)
    tw = wall_seconds() - w0
    call cpu_time(tcpu)
    tcpu = tcpu - c0
    call stop_on(e)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    ! momentum: what the symmetry conditions removed at the boundary nodes
    ! does not count, and the scale is sum m|u| (the total is near zero)
    change = [abs(m1 - m0)/m0, norm2(p1 - p0 + stats%momentum_constrained)/pscale, &
              abs(ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)]
  end subroutine time_remap

  !> One row of the rate table: count items in tw seconds of wall time (tcpu of CPU time).
  subroutine row(label, count, tw, tcpu)
    character(len=*), intent(in) :: label
    integer, intent(in) :: count
    real(wp), intent(in) :: tw, tcpu
    real(wp) :: rate
    character(len=12) :: lab
    lab = label
    rate = real(count, wp)/max(tw, tiny(1.0_wp))
    write(*, '(a12,i8,f11.3,es12.3,es14.3,f13.1,f10.3)') lab, count, tw, rate, rate/nthreads, &
      1.0e6_wp*tw*nthreads/max(count, 1), tcpu
  end subroutine row

  !> What remap_euler_step reported for one run, and conservation.
  subroutine stats_block(label, s, change)
    character(len=*), intent(in) :: label
    type(remap_stats_t), intent(in) :: s
    real(wp), intent(in) :: change(3)
    write(*, '(a,a,i0,a,i0,a,i0)') label, ' stats: cells remapped ', s%cells_remapped, ', copied ', &
      s%cells_copied, ', reach ', s%reach
    write(*, '(a,i0,a,f6.2,a,i0,a,es9.2)') '    MoF cells ', s%mof_cells, ', mean iterations ', &
      real(s%mof_iterations, wp)/real(max(s%mof_cells, 1), wp), ', not converged ', s%mof_not_converged, &
      ', largest centroid error/size ', s%mof_err_max
    write(*, '(a,es9.2,a,es9.2,a,i0,a,i0,a,es10.3)') '    volume defect ', s%volume_defect, &
      ', given defect ', s%given_defect, ', regions rescaled ', s%regions_rescaled, ', slivers merged ', &
      s%slivers_merged, ', KE to internal ', s%ke_to_internal
    write(*, '(a,3f9.3,a)') '    phases [s]: prepare, intersect, assemble ', s%t_prepare, s%t_intersect, &
      s%t_assemble, ' (remap_stats_t timers)'
    write(*, '(a,3es10.2)') '    relative change of mass, momentum (+ constrained, / sum m|u|), total energy ', &
      change
  end subroutine stats_block

  !> MoF reconstructions of random planes in three kinds of hexahedra.
  subroutine bench_mof()
    character(len=12), parameter :: kind_name(3) = [character(len=12) :: 'mof_cube', 'mof_perturb', 'mof_sheared']
    type(rng_t) :: rng
    real(wp), allocatable :: xs(:, :, :), vf(:), cref(:, :)
    real(wp) :: nrm(3), d, v, c(3), emax, w0, tw, c0, tc, en, dd
    integer :: kind, i, itsum, ncap, nfail, it, itmax, stat
    logical :: ok
    character(len=200) :: msg
    type(error_t), allocatable :: e

    allocate(xs(3, 8, nmof), vf(nmof), cref(3, nmof), stat=stat, errmsg=msg)
    if (stat /= 0) call error_set(e, 'bench_mof', 'cannot allocate: '//trim(msg))
    call stop_on(e)
    write(*, '(a,i0,a)') 'MoF (mof_reconstruct, cap ', mof_max_iter_default, ' iterations): random normal, '// &
      'volume fraction uniform in [0.01, 0.99]'
    write(*, '(a)') 'row          count    wall[s]   per_second  per_s_thread  us_x_thread    cpu[s]  mean_it'// &
      '  max_it  at_cap  failed  max_err/size'
    call rng_seed(rng, seed + 1)
    do kind = 1, 3
      ! the samples (not timed)
      do i = 1, nmof
        call random_hex(rng, kind, xs(:, :, i))
        do
          nrm = [2.0_wp*rng_uniform(rng) - 1.0_wp, 2.0_wp*rng_uniform(rng) - 1.0_wp, 2.0_wp*rng_uniform(rng) - 1.0_wp]
          en = norm2(nrm)
          if (en > 0.1_wp .and. en <= 1.0_wp) exit
        end do
        nrm = nrm/en
        vf(i) = 0.01_wp + 0.98_wp*rng_uniform(rng)
        call mof_plane_for_volume(xs(:, :, i), nrm, vf(i), dd, ok)
        call mof_cut_volume(xs(:, :, i), nrm, dd, v, c)
        vf(i) = v/hex_volume(xs(:, :, i))
        cref(:, i) = c
      end do
      itsum = 0
      itmax = 0
      ncap = 0
      nfail = 0
      emax = 0.0_wp
      call cpu_time(c0)
      w0 = wall_seconds()
      !$omp parallel do default(none) shared(xs, vf, cref, nmof) private(i, nrm, d, v, it, ok) &
      !$omp reduction(+:itsum, ncap, nfail) reduction(max:emax, itmax) schedule(dynamic, 64)
      do i = 1, nmof
        call mof_reconstruct(xs(:, :, i), vf(i), cref(:, i), nrm, d, v, it, ok)
        itsum = itsum + it
        itmax = max(itmax, it)
        emax = max(emax, v/hex_volume(xs(:, :, i))**(1.0_wp/3.0_wp))
        if (.not. ok) then
          if (it >= mof_max_iter_default) then
            ncap = ncap + 1
          else
            nfail = nfail + 1
          end if
        end if
      end do
      !$omp end parallel do
      tw = wall_seconds() - w0
      call cpu_time(tc)
      write(*, '(a12,i8,f11.3,es12.3,es14.3,f13.1,f10.3,f9.2,i8,i8,i8,es14.2)') kind_name(kind), nmof, tw, &
        nmof/max(tw, tiny(1.0_wp)), nmof/max(tw, tiny(1.0_wp))/nthreads, 1.0e6_wp*tw*nthreads/nmof, tc - c0, &
        real(itsum, wp)/nmof, itmax, ncap, nfail, emax
    end do
    write(*, '(a)') 'mof_cube: unit cube; mof_perturb: unit cube, nodes moved by up to 0.2 (non-planar faces);'
    write(*, '(a)') 'mof_sheared: unit cube sheared by 0.6 in x along y and z, then nodes moved by up to 0.1;'
    write(*, '(a)') 'at_cap: hit the iteration cap; failed: not ok below the cap; max_err: centroid error / cell size'
  end subroutine bench_mof

  !> Hex of kind k (1 unit cube, 2 unit cube with nodes moved by up to 0.2,
  !> 3 unit cube sheared by 0.6 in x along y and z, nodes moved by up to 0.1).
  subroutine random_hex(rng, k, xn)
    type(rng_t), intent(inout) :: rng
    integer, intent(in) :: k
    real(wp), intent(out) :: xn(3, 8)
    integer :: a, d
    do a = 1, 8
      xn(:, a) = real(hex_corner(:, a), wp)
      if (k == 3) xn(1, a) = xn(1, a) + 0.6_wp*(xn(2, a) + xn(3, a))
      if (k >= 2) then
        do d = 1, 3
          xn(d, a) = xn(d, a) + merge(0.2_wp, 0.1_wp, k == 2)*(2.0_wp*rng_uniform(rng) - 1.0_wp)
        end do
      end if
    end do
  end subroutine random_hex
end program bench_remap
