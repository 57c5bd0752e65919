!> Blast answers at the gauges: from a gauge's pressure history, its arrival
!> time, peak overpressure, positive-phase duration and positive impulse,
!> as an analyst reads them off a pressure trace (and as UFC 3-340-02 and
!> Kingery-Bulmash tabulate them).
!>
!> With the ambient pressure p0 the gauge's first row, the overpressure is
!> dp(t) = p(t) - p0 and, over the history (rows t_k, linear between rows):
!>  - peak: the largest dp and the first row that has it; the wave has
!>    arrived only if it exceeds blast_detection times |p0| (a gauge the
!>    shock has not reached still sees the exponentially small foot a
!>    captured shock runs ahead of itself, 1e-9 of p0 or less: not an
!>    arrival), else no arrival, duration or impulse;
!>  - arrival t_a: the first time dp reaches half the peak (the middle of
!>    the shock's rise: a captured shock is smeared over a few cells, and its
!>    middle is where the front is);
!>  - positive phase: from the last time before t_a that dp was <= 0 (or the
!>    first row) to the first time after the peak that dp falls to 0; its
!>    duration is counted from t_a; the phase has not ended when dp stays
!>    positive to the last row (duration and impulse then up to it, flagged);
!>  - positive impulse: the integral of dp over the positive phase
!>    (trapezoids, the end segments cut at the zero crossings).
!> `tools/blast_gauges.py` gives the same for any gauge file.
module io_blast
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa
  use io_gauges, only: read_line
  implicit none
  private
  public :: blast_t, blast_answers, blast_read_gauges, blast_detection

  !> The smallest overpressure, as a fraction of |p0|, that counts as an
  !> arrival: 1e-4 (10 Pa in the ISO atmosphere), below the smallest
  !> overpressure a blast chart tabulates (UFC 3-340-02: 0.1 psi, 690 Pa).
  real(wp), parameter :: blast_detection = 1.0e-4_wp

  !> One gauge's answers (time and pressure in the deck's units).
  type :: blast_t
    real(wp) :: ambient = 0.0_wp         !< p0, the first row's pressure
    real(wp) :: peak = 0.0_wp            !< largest overpressure
    real(wp) :: peak_time = 0.0_wp       !< its time
    real(wp) :: arrival = 0.0_wp         !< first time dp reaches peak/2
    real(wp) :: duration = 0.0_wp        !< positive phase from the arrival
    real(wp) :: impulse = 0.0_wp         !< integral of dp over the positive phase
    logical :: arrived = .false.         !< an overpressure above blast_detection |p0| seen
    logical :: ended = .false.           !< the positive phase ended within the history
  end type blast_t

contains

  !> The answers of one gauge's history p(k) at times t(k), k = 1..n.
  pure function blast_answers(t, p) result(b)
    real(wp), intent(in) :: t(:), p(:)
    type(blast_t) :: b
    real(wp) :: half, ts, te, dp0, dp1
    integer :: n, k, kp, ka, kz

    n = size(t)
    if (n == 0) return
    b%ambient = p(1)
    kp = 1
    do k = 2, n
      if (p(k) - b%ambient > p(kp) - b%ambient) kp = k
    end do
    b%peak = p(kp) - b%ambient
    b%peak_time = t(kp)
    b%arrived = b%peak > blast_detection*abs(b%ambient)
    if (.not. b%arrived) return
    half = 0.5_wp*b%peak
    ! arrival: the first row at or above half the peak, back to the crossing
    ka = 1
    do k = 1, kp
      if (p(k) - b%ambient >= half) then
        ka = k
        exit
      end if
    end do
    b%arrival = t(ka)
    if (ka > 1) b%arrival = crossing(t(ka - 1), t(ka), p(ka - 1) - b%ambient - half, p(ka) - b%ambient - half)
    ! the phase starts at the last dp <= 0 before the arrival
    ts = t(1)
    kz = 1
    do k = ka - 1, 1, -1
      if (p(k) - b%ambient <= 0.0_wp) then
        ts = crossing(t(k), t(k + 1), p(k) - b%ambient, p(k + 1) - b%ambient)
        kz = k + 1
        exit
      end if
    end do
    ! ... and ends at the first dp <= 0 after the peak
    te = t(n)
    b%ended = .false.
    b%impulse = 0.0_wp
    dp0 = 0.0_wp
    if (kz > 1) then
      b%impulse = 0.5_wp*(p(kz) - b%ambient)*(t(kz) - ts)   ! (the cut first segment)
    end if
    do k = kz, n - 1
      dp0 = p(k) - b%ambient
      dp1 = p(k + 1) - b%ambient
      if (k + 1 > kp .and. dp1 <= 0.0_wp) then
        te = crossing(t(k), t(k + 1), dp0, dp1)
        b%impulse = b%impulse + 0.5_wp*dp0*(te - t(k))
        b%ended = .true.
        exit
      end if
      b%impulse = b%impulse + 0.5_wp*(dp0 + dp1)*(t(k + 1) - t(k))
    end do
    b%duration = te - b%arrival

  contains

    !> Where the line through (ta, fa), (tb, fb) crosses zero (fa and fb of
    !> opposite signs or one of them zero).
    pure real(wp) function crossing(ta, tb, fa, fb) result(tc)
      real(wp), intent(in) :: ta, tb, fa, fb
      tc = tb
      if (abs(fa - fb) > 0.0_wp) tc = ta + (tb - ta)*fa/(fa - fb)
    end function crossing
  end function blast_answers

  !> Reads the times and each gauge's pressure history from a gauge file
  !> (`io_gauges`: `#` header lines, the last naming the columns, among them
  !> pressure_<g>): t(nrow), p(nrow, ngauge).
  subroutine blast_read_gauges(path, ngauge, t, p, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ngauge
    real(wp), allocatable, intent(out) :: t(:), p(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: line, header
    character(len=32), allocatable :: names(:)
    real(wp), allocatable :: row(:), tt(:), pp(:, :)
    integer, allocatable :: col(:)
    integer :: u, ios, n, g, k, nc, stat
    character(len=256) :: msg

    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'blast_read_gauges', 'cannot read '''//path//''': '//trim(msg))
      return
    end if
    header = ''
    n = 0
    allocate(col(ngauge), tt(64), pp(64, ngauge), stat=stat)
    if (stat /= 0) then
      close(u)
      call error_set(err, 'blast_read_gauges', error_no_memory('the gauge histories'))
      return
    end if
    col = 0
    do
      call read_line(u, line, ios)
      if (ios /= 0) exit
      if (len_trim(line) == 0) cycle
      if (index(adjustl(line), '#') == 1) then
        header = adjustl(line)
        cycle
      end if
      if (n == 0) then
        ! the columns from the last header line
        nc = count_words(header) - 1
        allocate(names(nc), row(nc), stat=stat)
        if (stat /= 0) exit
        read(header(2:), *, iostat=ios) names
        if (ios /= 0) exit
        do g = 1, ngauge
          do k = 1, nc
            if (names(k) == 'pressure_'//itoa(g)) col(g) = k
          end do
        end do
        if (any(col == 0) .or. names(1) /= 'time') then
          ios = 1
          exit
        end if
      end if
      read(line, *, iostat=ios) row
      if (ios /= 0) exit
      n = n + 1
      if (n > size(tt)) then
        call grow(stat)
        if (stat /= 0) exit
      end if
      tt(n) = row(1)
      pp(n, :) = row(col)
    end do
    close(u)
    if (stat /= 0) then
      call error_set(err, 'blast_read_gauges', error_no_memory('the gauge histories'))
      return
    end if
    if (ios > 0 .or. (n == 0 .and. len(header) == 0)) then
      call error_set(err, 'blast_read_gauges', 'cannot read the gauge histories of '''//path//'''')
      return
    end if
    t = tt(1:n)
    p = pp(1:n, :)

  contains

    subroutine grow(st)
      integer, intent(out) :: st
      real(wp), allocatable :: t2(:), p2(:, :)
      allocate(t2(2*size(tt)), p2(2*size(tt), ngauge), stat=st)
      if (st /= 0) return
      t2(1:size(tt)) = tt
      p2(1:size(tt), :) = pp
      call move_alloc(t2, tt)
      call move_alloc(p2, pp)
    end subroutine grow
  end subroutine blast_read_gauges

  pure integer function count_words(s) result(n)
    character(len=*), intent(in) :: s
    integer :: i
    logical :: inword
    n = 0
    inword = .false.
    do i = 1, len_trim(s)
      if (s(i:i) /= ' ') then
        if (.not. inword) n = n + 1
        inword = .true.
      else
        inword = .false.
      end if
    end do
  end function count_words

end module io_blast
