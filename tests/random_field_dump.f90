!> Writes, as hexadecimal bit patterns, a correlated random field, its
!> samples at off-node points and the void fractions from them, and a
!> Gaussian field's part around a box with samples in it, for
!> random_field_threads.sh to compare across OMP_NUM_THREADS. The grid
!> (3D, ~10^6 nodes) is large enough that every threaded loop of
!> strength_random_field splits over the threads.
!> Usage: random_field_dump OUTFILE
program random_field_dump
  use base_kinds, only: wp, i8
  use base_errors, only: error_t
  use strength_random_field, only: random_field_t, random_field_build, random_field_sample, void_fraction_from_field
  implicit none
  type(random_field_t) :: f
  type(error_t), allocatable :: err
  real(wp), allocatable :: x(:, :), g(:), f0(:)
  real(wp) :: clipped
  integer :: p, np, ntrunc, u, ios, i, j, k
  character(len=256) :: path

  call get_command_argument(1, path)
  if (len_trim(path) == 0) error stop 'usage: random_field_dump OUTFILE'
  call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [12.0_wp, 10.0_wp, 8.0_wp], 0.4_wp, 1.2_wp, 'exponential', 31, f, &
                          clipped, err)
  if (allocated(err)) error stop 'random_field_dump: build failed'
  ! points off the nodes: an irregular (but fixed) pattern inside the box
  np = 20000
  allocate(x(3, np), g(np), f0(np))
  do p = 1, np
    x(:, p) = [12.0_wp, 10.0_wp, 8.0_wp]*[modulo(0.6180339887_wp*p, 1.0_wp), modulo(0.7548776662_wp*p, 1.0_wp), &
                                          modulo(0.5698402910_wp*p, 1.0_wp)]
  end do
  call random_field_sample(f, x, g, err)
  if (allocated(err)) error stop 'random_field_dump: sample failed'
  call void_fraction_from_field(g, 0.005_wp, 0.0003_wp, 'normal', f0, ntrunc, err)
  if (allocated(err)) error stop 'random_field_dump: void fraction failed'
  open(newunit=u, file=trim(path), status='replace', action='write', iostat=ios)
  if (ios /= 0) error stop 'random_field_dump: cannot open the output'
  write(u, '(a,3i6,a,z16.16,a,i0)') 'grid', f%n, ' clipped ', transfer(clipped, 0_i8), ' ntrunc ', ntrunc
  do k = 1, f%n(3)
    do j = 1, f%n(2)
      do i = 1, f%n(1)
        write(u, '(z16.16)') transfer(f%values(i, j, k), 0_i8)
      end do
    end do
  end do
  do p = 1, np
    write(u, '(z16.16,1x,z16.16)') transfer(g(p), 0_i8), transfer(f0(p), 0_i8)
  end do
  ! the Gaussian covariance's separable build (its passes are threaded),
  ! on the part of the grid around a box, sampled at the points in it
  call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [12.0_wp, 10.0_wp, 8.0_wp], 0.4_wp, 1.2_wp, 'gaussian', 37, f, &
                          clipped, err, box_lo=[2.0_wp, 1.0_wp, 0.5_wp], box_hi=[10.0_wp, 9.0_wp, 7.0_wp])
  if (allocated(err)) error stop 'random_field_dump: gaussian build failed'
  do p = 1, np
    x(:, p) = [2.0_wp, 1.0_wp, 0.5_wp] + [8.0_wp, 8.0_wp, 6.5_wp]*[modulo(0.6180339887_wp*p, 1.0_wp), &
              modulo(0.7548776662_wp*p, 1.0_wp), modulo(0.5698402910_wp*p, 1.0_wp)]
  end do
  call random_field_sample(f, x, g, err)
  if (allocated(err)) error stop 'random_field_dump: gaussian sample failed'
  write(u, '(a,3i6,a,3i6)') 'gaussian part', shape(f%values), ' from node', f%first
  do k = 1, size(f%values, 3)
    do j = 1, size(f%values, 2)
      do i = 1, size(f%values, 1)
        write(u, '(z16.16)') transfer(f%values(i, j, k), 0_i8)
      end do
    end do
  end do
  do p = 1, np
    write(u, '(z16.16)') transfer(g(p), 0_i8)
  end do
  close(u)
  write(*, '(a,3i6,a,i0,a)') 'random_field_dump: grid', f%n, ', ', np, ' points written (exponential and gaussian)'
end program random_field_dump
