!> Per-material and per-body sums (the analyst's MATSUM): mass, momentum,
!> kinetic and internal energy and volume of each grid material and of each
!> particle body, exact sums over the blocks (`base_xsum`: the same on any rank or
!> thread count), for the history file `<dir>/<name>_matsum.txt` and the
!> final report.
!>
!> The grid's kinetic energy and momentum live on the nodes. A material's
!> share is booked through the corner (subcell) masses: corner a of cell c
!> carries m_ca u_n (n its node) and 1/2 m_ca |u_n|^2, and the material takes
!> the fraction of them that its mass is of the cell's (1 in a pure cell).
!> Since the corner masses of a node sum to its mass, the materials' shares
!> add up to the grid's nodal totals to round-off. A material's volume is
!> its volume fraction of each cell times the cell's volume (a bubble's
!> volume history). A body's sums are its particles' own: sum m_p,
!> sum m_p v_p, sum 1/2 m_p |v_p|^2, sum m_p e_p, sum V_p.
!> (The log's kinetic total books the particles through the nodes they
!> move, so a body's kinetic energy and the particles' nodal share differ
!> by what the coupling's interpolation smooths.)
module driver_matsum
  use base_kinds, only: wp
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use driver_state, only: state_t
  implicit none
  private
  public :: matsum_t, matsum_compute, matsum_header, matsum_rows, nsum

  !> Quantities per row: mass, momentum (3), kinetic, internal, volume.
  integer, parameter :: nsum = 7

  !> The sums: column k of `mat` is material k's, of `body` body k's (each
  !> mass, momentum x y z, kinetic, internal, volume).
  type :: matsum_t
    real(wp), allocatable :: mat(:, :)    !< (nsum, nmat)
    real(wp), allocatable :: body(:, :)   !< (nsum, nbody); nbody 0 without particles
  end type matsum_t

contains

  !> The sums of the state `st` (collective: every rank calls it).
  subroutine matsum_compute(st, ms)
    type(state_t), intent(in) :: st
    type(matsum_t), intent(out) :: ms
    ! the sums of material k (body k) at nsum*(k-1)+1 .. nsum*k
    type(xsum_t) :: acc(nsum*size(st%mats))
    integer :: nm, nb, c, m, s, i, j, k, n, n0, q
    real(wp) :: frac, mc

    nm = size(st%mats)
    do k = st%g%clo(3), st%g%chi(3)
      do j = st%g%clo(2), st%g%chi(2)
        do i = st%g%clo(1), st%g%chi(1)
          c = st%g%cell(i, j, k)
          m = st%h%mat(c)
          n0 = st%g%cell_node0(i, j, k)
          if (m > 0) then
            call add_cell(m, 1.0_wp, st%h%mass(c), st%h%mass(c)*st%h%e(c), st%h%vol(c))
          else if (m < 0) then
            mc = st%h%mass(c)
            do s = st%mx%start(-m), st%mx%start(-m + 1) - 1
              frac = 0.0_wp
              if (mc > 0.0_wp) frac = st%mx%mass(s)/mc
              call add_cell(st%mx%mat(s), frac, st%mx%mass(s), st%mx%mass(s)*st%mx%e(s), &
                            st%mx%vf(s)*st%h%vol(c))
            end do
          end if
        end do
      end do
    end do
    call st%halo%sums(acc)
    ms%mat = reshape([(xsum_value(acc(q)), q = 1, nsum*nm)], [nsum, nm])

    nb = 0
    if (allocated(st%pt%body)) then
      do k = 1, st%pt%np
        if (owns(k)) nb = max(nb, st%pt%body(k))
      end do
    end if
    call st%halo%max_int(nb)
    call body_sums(nb)

  contains

    !> The block owns particle p (one block without ownership marks: all).
    logical function owns(p)
      integer, intent(in) :: p
      owns = .true.
      if (allocated(st%pw%owned)) owns = st%pw%owned(p)
    end function owns

    !> The sums of bodies 1..nb over the particles the block owns.
    subroutine body_sums(nb)
      integer, intent(in) :: nb
      type(xsum_t) :: bacc(nsum*nb)
      integer :: p, r, d
      do p = 1, merge(st%pt%np, 0, allocated(st%pt%body))
        if (.not. owns(p)) cycle
        r = nsum*(st%pt%body(p) - 1)
        call xsum_add(bacc(r + 1), st%pt%m(p))
        do d = 1, 3
          call xsum_add(bacc(r + 1 + d), st%pt%m(p)*st%pt%v(d, p))
        end do
        call xsum_add(bacc(r + 5), 0.5_wp*st%pt%m(p)*dot_product(st%pt%v(:, p), st%pt%v(:, p)))
        call xsum_add(bacc(r + 6), st%pt%m(p)*st%pt%e(p))
        call xsum_add(bacc(r + 7), st%pt%vol(p))
      end do
      if (nb > 0) call st%halo%sums(bacc)
      ms%body = reshape([(xsum_value(bacc(r)), r = 1, nsum*nb)], [nsum, nb])
    end subroutine body_sums

    !> Books material mm's mass, internal energy and volume in the cell,
    !> and its fraction `f` of the cell's corner momenta and kinetic energies.
    subroutine add_cell(mm, f, mass, internal, volume)
      integer, intent(in) :: mm
      real(wp), intent(in) :: f, mass, internal, volume
      integer :: aa, d, r
      real(wp) :: mcf
      r = nsum*(mm - 1)
      call xsum_add(acc(r + 1), mass)
      call xsum_add(acc(r + 6), internal)
      call xsum_add(acc(r + 7), volume)
      do aa = 1, 8
        n = n0 + st%g%corner_offset(aa)
        mcf = f*st%h%mcorner(aa, c)
        do d = 1, 3
          call xsum_add(acc(r + 1 + d), mcf*st%h%u(d, n))
        end do
        call xsum_add(acc(r + 5), 0.5_wp*mcf*dot_product(st%h%u(:, n), st%h%u(:, n)))
      end do
    end subroutine add_cell
  end subroutine matsum_compute

  !> The file's header lines (`dt_text`: the row interval, as written).
  function matsum_header(dt_text) result(lines)
    character(len=*), intent(in) :: dt_text
    character(len=200) :: lines(3)
    lines(1) = '# material and body sums (lsalepm): rows every &output history_dt = '//dt_text// &
               ' and at the end, one per grid material and per particle body'
    lines(2) = '# kinetic and momentum of a material: its mass share of the cells'' corner (nodal) values; '// &
               'of a body: its particles''; deck units'
    lines(3) = '# time kind index name mass momentum_x momentum_y momentum_z kinetic internal volume'
  end function matsum_header

  !> One row per material (kind `material`, index, name) and per body
  !> (kind `body`, index, name body_<index>) at time t.
  function matsum_rows(t, ms, names) result(rows)
    real(wp), intent(in) :: t
    type(matsum_t), intent(in) :: ms
    character(len=*), intent(in) :: names(:)
    character(len=300) :: rows(size(ms%mat, 2) + size(ms%body, 2))
    character(len=32) :: label
    integer :: m, nm, nb
    nm = size(ms%mat, 2)
    nb = size(ms%body, 2)
    do m = 1, nm
      write(rows(m), '(es25.16e3,1x,a,1x,i0,1x,a,7es25.16e3)') t, 'material', m, trim(names(m)), ms%mat(:, m)
    end do
    do m = 1, nb
      write(label, '(a,i0)') 'body_', m
      write(rows(nm + m), '(es25.16e3,1x,a,1x,i0,1x,a,7es25.16e3)') t, 'body', m, trim(label), ms%body(:, m)
    end do
  end function matsum_rows
end module driver_matsum
