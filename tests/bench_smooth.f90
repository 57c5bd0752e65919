!> Benchmark of the mesh smoothers (not a test: it asserts nothing and is run
!> by `make bench` through tools/bench.sh, never by ctest): the smoothing
!> benchmark of the paper's Sect. 7.1 (Fig. 16).
!>
!> An n^3 grid (default 50^3) of unit spacing; every interior node moved by
!> a uniform random displacement in [-amp, amp] in each direction (amp =
!> 0.399, seeded with base_random); boundary nodes are not moved, and during
!> smoothing they slide by the rules of Sect. 5.3.2 (face nodes in their
!> face, edge nodes along their edge, corners fixed). All cells are active.
!> For the original GETMe, the modified GETMe, the weighted average and the
!> combined method (one modified GETMe pass then one weighted-average pass
!> per iteration), Q_min (Eq. 46) after each iteration and the cumulative
!> CPU time (cpu_time: the process's time over all threads) and wall time
!> of the passes and the Q_min evaluation, up to n_iter iterations (default
!> 100) or Q_min > q_stop = 0.9999. Then the tangled variant (amp = 0.45:
!> cells with negative corner Jacobians): the combined method, and the
!> iteration after which every cell is valid again (all corner Jacobians,
!> hence all volumes, positive).
!>
!> Writes a table to standard output and CSV rows (iteration, method, q_min,
!> seconds, wall_seconds; seconds = cumulative CPU time, iteration 0 = the
!> initial grid) to the file given (default smoothing.csv);
!> tools/plot_smoothing.py draws them. Usage:
!>   bench_smooth [n [n_iter [csv [seed]]]]          (defaults 50 100 smoothing.csv 2024)
program bench_smooth
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use base_timers, only: wall_seconds
  use mesh_geometry, only: hex_volume
  use mesh_grid, only: block_gather
  use rezone_smooth, only: smooth_mobility_t, smooth_region_t, smooth_mobility_box, smooth_region_init, &
                           smooth_modified_getme, smooth_weighted_average, smooth_getme_original, &
                           smooth_q_min, hex_min_tet_volume, hex_min_corner_jacobian
  use omp_lib, only: omp_get_max_threads
  implicit none
  real(wp), parameter :: amp = 0.399_wp, q_stop = 0.9999_wp
  !> Amplitudes of the tangled variants: 0.45 (negative corner Jacobians and
  !> 24-tet split tetrahedra, but no cell of negative volume) and 0.7 (nodes
  !> pass their neighbours: cells of negative volume too).
  real(wp), parameter :: amp_tangled(2) = [0.45_wp, 0.7_wp]
  character(len=*), parameter :: names(4) = [character(len=16) :: 'getme', 'modified_getme', &
                                                                  'weighted_average', 'combined']
  integer :: n, n_iter, seed, nnode, ncell, u, ios, m, it, niter(4), nbad(3)
  real(wp), allocatable :: x0(:, :), x(:, :)
  !> Q_min and cumulative CPU seconds after each iteration (0:n_iter, method)
  real(wp), allocatable :: qh(:, :), th(:, :)
  logical, allocatable :: active(:)
  real(wp) :: q0, q, wall(4), t0, t1, w0, c_acc, w_acc, vmin(3)
  character(len=256) :: csv
  character(len=300) :: msg
  type(smooth_mobility_t) :: mob
  type(smooth_region_t) :: reg
  type(error_t), allocatable :: err

  call read_arguments(n, n_iter, csv, seed)
  nnode = (n + 1)**3
  ncell = n**3
  allocate(x0(3, nnode), x(3, nnode), active(ncell), qh(0:n_iter, 4), th(0:n_iter, 4))
  active = .true.
  call smooth_mobility_box(n, n, n, mob, err, boundary='slide')
  if (.not. allocated(err)) call smooth_region_init(mob, active, reg, err)
  if (allocated(err)) then
    write(*, '(a)') 'bench_smooth: '//err%where//': '//err%msg
    error stop 1
  end if
  open(newunit=u, file=trim(csv), status='replace', action='write', iostat=ios, iomsg=msg)
  if (ios /= 0) then
    write(*, '(a)') 'bench_smooth: cannot open '//trim(csv)//': '//trim(msg)
    error stop 1
  end if
  write(u, '(a)') 'iteration,method,q_min,seconds,wall_seconds'

  call perturbed_grid(n, amp, seed, x0)
  q0 = smooth_q_min(reg, x0)
  write(*, '(a,i0,a,i0,a,i0)') '# Smoothing benchmark (Sect. 7.1): ', n, '^3 cells, unit spacing, ', &
    omp_get_max_threads(), ' thread(s), seed ', seed
  write(*, '(a,f5.3,a,f5.3,a)') '# interior nodes moved by U[-', amp, ', +', amp, &
    '] per direction; boundary nodes slide (faces in their plane, edges along their line, corners fixed)'
  write(*, '(a,f7.4,a)') '# initial Q_min = ', q0, ' (paper: 0.3010)'
  call grid_validity(n, x0, vmin, nbad)
  call report_validity('# initial grid', vmin, nbad)

  do m = 1, 4
    x = x0
    c_acc = 0.0_wp
    w_acc = 0.0_wp
    niter(m) = n_iter
    qh(:, m) = q0
    th(:, m) = 0.0_wp
    write(u, '(i0,",",a,",",es23.16,",",es12.5,",",es12.5)') 0, trim(names(m)), q0, 0.0_wp, 0.0_wp
    do it = 1, n_iter
      call cpu_time(t0)
      w0 = wall_seconds()
      select case (m)
      case (1)
        call smooth_getme_original(reg, x)
      case (2)
        call smooth_modified_getme(reg, x)
      case (3)
        call smooth_weighted_average(reg, x)
      case (4)
        call smooth_modified_getme(reg, x)
        call smooth_weighted_average(reg, x)
      end select
      q = smooth_q_min(reg, x)
      call cpu_time(t1)
      c_acc = c_acc + (t1 - t0)
      w_acc = w_acc + (wall_seconds() - w0)
      qh(it, m) = q
      th(it, m) = c_acc
      write(u, '(i0,",",a,",",es23.16,",",es12.5,",",es12.5)') it, trim(names(m)), q, c_acc, w_acc
      if (q > q_stop) then
        niter(m) = it
        exit
      end if
    end do
    wall(m) = w_acc
  end do

  ! iterations and cumulative CPU seconds to reach each quality level
  write(*, '(a)') ''
  write(*, '(a)') '| method           | Q_min > 0.99 | Q_min > 0.999 | Q_min > 0.9999 | final Q_min | CPU s | wall s |'// &
    ' CPU ms/iter |'
  write(*, '(a)') '|------------------|--------------|---------------|----------------|-------------|-------|--------|'// &
    '-------------|'
  do m = 1, 4
    write(*, '("| ",a16," |",3(a,"|")," ",f11.6," | ",f5.2," | ",f6.2," | ",f11.1," |")') names(m), &
      reach(m, 0.99_wp, 14), reach(m, 0.999_wp, 15), reach(m, q_stop, 16), qh(niter(m), m), th(niter(m), m), &
      wall(m), 1e3_wp*th(niter(m), m)/niter(m)
  end do
  write(*, '(a)') '# (cells: iterations, cumulative CPU seconds in brackets; - = not reached in the iterations run)'
  if (qh(niter(4), 4) > q_stop) then
    do m = 1, 3
      if (qh(niter(m), m) > q_stop) then
        write(*, '(a,a,a,f6.2)') '# CPU time to Q_min > 0.9999, ', trim(names(m)), ' / combined: ', &
          th(niter(m), m)/th(niter(4), 4)
      else
        write(*, '(a,a,a,i0,a,f6.2,a)') '# ', trim(names(m)), ' after ', niter(m), ' iterations (', &
          th(niter(m), m)/th(niter(4), 4), ' x the CPU time of combined) still below 0.9999'
      end if
    end do
  end if

  ! the tangled variants: combined smoothing until every cell is valid, then on to q_stop
  do m = 1, size(amp_tangled)
    call run_tangled(amp_tangled(m))
  end do
  close(u)
  write(*, '(a)') '# CSV: '//trim(csv)

contains

  !> The combined method on the grid perturbed by amp_t: Q_min per
  !> iteration (CSV method combined_tangled_<amp_t>), the iteration after
  !> which every cell is valid, and the one that reaches q_stop.
  subroutine run_tangled(amp_t)
    real(wp), intent(in) :: amp_t
    character(len=32) :: label
    integer :: it, it_valid, it_q, nbad(3)
    real(wp) :: q, vmin(3), t0, t1, w0, c_acc, w_acc

    write(label, '(a,f4.2)') 'combined_tangled_', amp_t
    call perturbed_grid(n, amp_t, seed, x)
    q = smooth_q_min(reg, x)
    call grid_validity(n, x, vmin, nbad)
    write(*, '(a)') ''
    write(*, '(a,f5.3,a,f8.4)') '# tangled variant, amp = ', amp_t, ': initial Q_min = ', q
    call report_validity('# initial grid', vmin, nbad)
    write(u, '(i0,",",a,",",es23.16,",",es12.5,",",es12.5)') 0, trim(label), q, 0.0_wp, 0.0_wp
    it_valid = -1
    it_q = -1
    c_acc = 0.0_wp
    w_acc = 0.0_wp
    if (all(nbad == 0)) it_valid = 0
    do it = 1, n_iter
      call cpu_time(t0)
      w0 = wall_seconds()
      call smooth_modified_getme(reg, x)
      call smooth_weighted_average(reg, x)
      q = smooth_q_min(reg, x)
      call cpu_time(t1)
      c_acc = c_acc + (t1 - t0)
      w_acc = w_acc + (wall_seconds() - w0)
      write(u, '(i0,",",a,",",es23.16,",",es12.5,",",es12.5)') it, trim(label), q, c_acc, w_acc
      call grid_validity(n, x, vmin, nbad)
      if (it_valid < 0 .and. all(nbad == 0)) then
        it_valid = it
        write(*, '(a,i0,a,f8.4)') '# combined: every cell valid after ', it, ' iteration(s), Q_min = ', q
        call report_validity('# that grid', vmin, nbad)
      end if
      if (q > q_stop) then
        it_q = it
        exit
      end if
    end do
    if (it_valid < 0) then
      write(*, '(a,i0,a)') '# combined: NOT untangled after ', n_iter, ' iterations'
      call report_validity('# last grid', vmin, nbad)
    end if
    if (it_q > 0) then
      write(*, '(a,i0,a,f6.2,a,f6.2,a)') '# combined: Q_min > 0.9999 after ', it_q, ' iterations, ', c_acc, &
        ' s CPU, ', w_acc, ' s wall'
    else
      write(*, '(a,i0,a,f8.5)') '# combined: Q_min after ', n_iter, ' iterations ', q
    end if
  end subroutine run_tangled

  !> Table cell of width w: the first iteration of method m with Q_min > level
  !> and the CPU seconds to it, or '-'.
  function reach(m, level, w) result(cell)
    integer, intent(in) :: m, w
    real(wp), intent(in) :: level
    character(len=w) :: cell
    integer :: i
    cell = ' -'
    do i = 1, niter(m)
      if (qh(i, m) > level) then
        write(cell, '(1x,i3," (",f5.2,")")') i, th(i, m)
        exit
      end if
    end do
  end function reach

  !> Optional arguments: n, n_iter, csv, seed.
  subroutine read_arguments(n, n_iter, csv, seed)
    integer, intent(out) :: n, n_iter, seed
    character(len=*), intent(out) :: csv
    character(len=256) :: arg
    integer :: st
    n = 50
    n_iter = 100
    csv = 'smoothing.csv'
    seed = 2024
    if (command_argument_count() >= 1) then
      call get_command_argument(1, arg)
      read(arg, *, iostat=st) n
      if (st /= 0 .or. n < 2) error stop 'bench_smooth: n must be an integer >= 2'
    end if
    if (command_argument_count() >= 2) then
      call get_command_argument(2, arg)
      read(arg, *, iostat=st) n_iter
      if (st /= 0 .or. n_iter < 1) error stop 'bench_smooth: n_iter must be an integer >= 1'
    end if
    if (command_argument_count() >= 3) call get_command_argument(3, csv)
    if (command_argument_count() >= 4) then
      call get_command_argument(4, arg)
      read(arg, *, iostat=st) seed
      if (st /= 0) error stop 'bench_smooth: seed must be an integer'
    end if
  end subroutine read_arguments

  !> Unit grid of n^3 cells with every interior node moved by U[-a, a] per
  !> direction (the same draw sequence for any a).
  subroutine perturbed_grid(n, a, seed, x)
    integer, intent(in) :: n, seed
    real(wp), intent(in) :: a
    real(wp), intent(out) :: x(:, :)
    type(rng_t) :: rng
    integer :: i, j, k, d, nd
    call rng_seed(rng, seed)
    do k = 0, n
      do j = 0, n
        do i = 0, n
          nd = 1 + i + (n + 1)*(j + (n + 1)*k)
          x(:, nd) = real([i, j, k], wp)
          if (i > 0 .and. i < n .and. j > 0 .and. j < n .and. k > 0 .and. k < n) then
            do d = 1, 3
              x(d, nd) = x(d, nd) + a*(2.0_wp*rng_uniform(rng) - 1.0_wp)
            end do
          end if
        end do
      end do
    end do
  end subroutine perturbed_grid

  !> Validity of every cell: the smallest cell volume, tetrahedron of the
  !> 24-tet split and corner Jacobian (vmin(1:3)) and how many cells have a
  !> non-positive one of each (nbad(1:3)).
  subroutine grid_validity(n, x, vmin, nbad)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: vmin(3)
    integer, intent(out) :: nbad(3)
    integer :: ci, cj, ck, b1, b2, b3
    real(wp) :: xn(3, 8), v(3), v1, v2, v3
    v1 = huge(1.0_wp); v2 = v1; v3 = v1
    b1 = 0; b2 = 0; b3 = 0
    !$omp parallel do default(none) shared(n, x) private(ci, cj, ck, xn, v) &
    !$omp reduction(min: v1, v2, v3) reduction(+: b1, b2, b3) schedule(static)
    do ck = 1, n
      do cj = 1, n
        do ci = 1, n
          call block_gather(n, n, ci, cj, ck, x, xn)
          v = [hex_volume(xn), hex_min_tet_volume(xn), hex_min_corner_jacobian(xn)]
          v1 = min(v1, v(1)); v2 = min(v2, v(2)); v3 = min(v3, v(3))
          if (v(1) <= 0.0_wp) b1 = b1 + 1
          if (v(2) <= 0.0_wp) b2 = b2 + 1
          if (v(3) <= 0.0_wp) b3 = b3 + 1
        end do
      end do
    end do
    !$omp end parallel do
    vmin = [v1, v2, v3]
    nbad = [b1, b2, b3]
  end subroutine grid_validity

  !> One line on the validity counts of `grid_validity`.
  subroutine report_validity(what, vmin, nbad)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: vmin(3)
    integer, intent(in) :: nbad(3)
    write(*, '(a,": cells with volume <= 0: ",i0," (min ",es10.3,"), with a 24-tet split tetrahedron <= 0: ",i0, &
             &" (min ",es10.3,"), with a corner Jacobian <= 0: ",i0," (min ",es10.3,")")') &
      what, nbad(1), vmin(1), nbad(2), vmin(2), nbad(3), vmin(3)
  end subroutine report_validity
end program bench_smooth
