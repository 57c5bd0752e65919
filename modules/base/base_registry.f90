!> The restart registry: every quantity that makes up the state, registered
!> once by the package that owns it, with its units, where it lives and
!> whether a restart must have it.
!>
!> Writer, reader and restart-compatibility check (`io_restart`) walk the
!> registry, so a field a package registers cannot be forgotten by any of
!> them. An entry is a view of the owner's storage (a pointer): register after
!> allocation; after storage is reallocated (the mixed cells after a remap)
!> clear the registry and register again. The location says which count an
!> array's last dimension must match (nodes, cells, mixed-cell slots,
!> particles) so that a file from another grid is refused by name, and later
!> which range a rank owns.
module base_registry
  use base_kinds, only: wp
  implicit none
  private
  public :: registry_t, registry_entry_t, LOWER_NONE, LOWER_POSITIVE, LOWER_NONNEGATIVE, &
            LOC_GLOBAL, LOC_NODE, LOC_CELL, LOC_MIXED_CELL, LOC_MIXED_SLOT, &
            LOC_PARTICLE, location_name, K_REAL, K_INT, K_REAL_SCALAR, K_INT_SCALAR

  !> Where a quantity lives. LOC_GLOBAL: a scalar or an array of the whole
  !> run; the others: an array whose last dimension runs over that entity.
  integer, parameter :: LOC_GLOBAL = 0, LOC_NODE = 1, LOC_CELL = 2, LOC_MIXED_CELL = 3, LOC_MIXED_SLOT = 4, &
                        LOC_PARTICLE = 5
  character(len=*), parameter :: loc_names(0:5) = [character(len=16) :: &
    'global', 'node', 'cell', 'mixed cell', 'mixed slot', 'particle']

  !> The range a quantity must be in to be a valid state (checked when a
  !> restart is read): any value, > 0 (masses, volumes, densities), >= 0
  !> (sound speeds, times, counts).
  integer, parameter :: LOWER_NONE = 0, LOWER_POSITIVE = 1, LOWER_NONNEGATIVE = 2

  integer, parameter :: K_REAL = 1, K_INT = 2, K_REAL_SCALAR = 3, K_INT_SCALAR = 4

  !> One registered quantity: a view of the owner's storage.
  type :: registry_entry_t
    character(len=64) :: name = ''
    character(len=32) :: units = ''
    integer :: kind = 0
    integer :: location = LOC_GLOBAL
    logical :: mandatory = .true.     !< a restart file without it is refused
    integer :: lower = LOWER_NONE     !< the range of a valid value
    integer, allocatable :: dims(:)
    real(wp), pointer, contiguous :: r(:) => null()
    integer, pointer, contiguous :: i(:) => null()
    real(wp), pointer :: rs => null()
    integer, pointer :: is => null()
  end type registry_entry_t

  !> The registry of one dump or read.
  type :: registry_t
    type(registry_entry_t), allocatable :: e(:)
    integer :: n = 0
  contains
    procedure, private :: add_r1, add_r2, add_i1, add_rs, add_is
    !> Registers an array (with its location) or a scalar under a name, with
    !> its units; `mandatory` (default true) says a restart must hold it,
    !> `lower` (default LOWER_NONE) the range of a valid value.
    generic :: add => add_r1, add_r2, add_i1, add_rs, add_is
    !> Forgets every registered quantity (the storage itself is untouched).
    procedure :: clear => registry_clear
  end type registry_t

contains

  !> The name of a location, for messages.
  pure function location_name(loc) result(name)
    integer, intent(in) :: loc
    character(len=:), allocatable :: name
    name = trim(loc_names(max(0, min(5, loc))))
  end function location_name

  subroutine push(this, name, units, kind, location, dims, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    integer, intent(in) :: kind, location, dims(:)
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    type(registry_entry_t) :: blank(32)
    ! grown by assignment, 32 entries at a time (a few dozen in all)
    if (.not. allocated(this%e)) this%e = blank
    if (this%n == size(this%e)) this%e = [this%e, blank]
    this%n = this%n + 1
    this%e(this%n)%name = name
    this%e(this%n)%units = units
    this%e(this%n)%kind = kind
    this%e(this%n)%location = location
    this%e(this%n)%dims = dims
    this%e(this%n)%mandatory = .true.
    if (present(mandatory)) this%e(this%n)%mandatory = mandatory
    this%e(this%n)%lower = LOWER_NONE
    if (present(lower)) this%e(this%n)%lower = lower
  end subroutine push

  subroutine registry_clear(this)
    class(registry_t), intent(inout) :: this
    if (allocated(this%e)) deallocate(this%e)
    this%n = 0
  end subroutine registry_clear

  subroutine add_r1(this, name, units, location, a, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    integer, intent(in) :: location
    real(wp), intent(inout), target, contiguous :: a(:)
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    call push(this, name, units, K_REAL, location, shape(a), mandatory, lower)
    this%e(this%n)%r => a
  end subroutine add_r1

  subroutine add_r2(this, name, units, location, a, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    integer, intent(in) :: location
    real(wp), intent(inout), target, contiguous :: a(:, :)
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    call push(this, name, units, K_REAL, location, shape(a), mandatory, lower)
    this%e(this%n)%r(1:size(a)) => a
  end subroutine add_r2

  subroutine add_i1(this, name, units, location, a, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    integer, intent(in) :: location
    integer, intent(inout), target, contiguous :: a(:)
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    call push(this, name, units, K_INT, location, shape(a), mandatory, lower)
    this%e(this%n)%i => a
  end subroutine add_i1

  subroutine add_rs(this, name, units, a, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    real(wp), intent(inout), target :: a
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    call push(this, name, units, K_REAL_SCALAR, LOC_GLOBAL, [integer ::], mandatory, lower)
    this%e(this%n)%rs => a
  end subroutine add_rs

  subroutine add_is(this, name, units, a, mandatory, lower)
    class(registry_t), intent(inout) :: this
    character(len=*), intent(in) :: name, units
    integer, intent(inout), target :: a
    logical, intent(in), optional :: mandatory
    integer, intent(in), optional :: lower
    call push(this, name, units, K_INT_SCALAR, LOC_GLOBAL, [integer ::], mandatory, lower)
    this%e(this%n)%is => a
  end subroutine add_is
end module base_registry
