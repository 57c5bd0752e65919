!> The plan of an Euler step remapped in parts of the way (&rezone
!> swept_parts): the decisions that take the grid from the Lagrangian
!> positions to the rezoned ones in parts, each remapped in full
!> (conservative), by swept faces where it can. The same decisions on one
!> process's grid and on a decomposed run's windows (whose counts are
!> reduced over the ranks before they are given here), so both take the
!> same parts.
!>
!> The first part takes every node as far as the swept faces allow in one
!> go (`first`: the caller's `remap_part_target` at fac times swept_max);
!> the rest of the way goes in nleft equal parts that keep every moving cell
!> within swept_max. A part the swept faces cannot take though its nodes
!> stay within swept_max (a cell it tangles on the way) is split
!> (`wants_split`, `split`); one whose swept faces break a material's bounds
!> is taken again at half the distance (`unbounded`), while the parts stay
!> within nmax (`room`); the last part the deck allows goes the rest of the
!> way (`last`). With no split left, a part some cells cannot take is
!> rescued around them (&rezone swept_hybrid, `wants_rescue`): stage 1 by
!> swept faces to the part's grid less the moves of the nodes around those
!> cells, stage 2 the rest of the way by intersection, or stage 3, the whole
!> part by intersection, when stage 1 cannot sweep or breaks a bound too
!> (`rescue_next`, `unbounded`). `taken` counts a part remapped.
module remap_parts
  use base_kinds, only: wp
  implicit none
  private
  public :: remap_parts_t

  type :: remap_parts_t
    integer :: nmax = 1            !< the most parts a step takes (&rezone swept_parts)
    logical :: hybrid = .false.    !< a part may be rescued around its cells (&rezone swept_hybrid)
    integer :: ntaken = 0          !< the parts taken
    integer :: nleft = 0           !< the equal parts left of the way (0: before the first part)
    integer :: nsplit = 0          !< the parts split
    integer :: nrescue = 0         !< the parts rescued
    integer :: rescue = 0          !< the stage of a part's rescue (0: none; module header)
    real(wp) :: fac = 1.0_wp       !< the first part's fraction of the swept-face bound
  contains
    procedure :: first => parts_first
    procedure :: room => parts_room
    procedure :: last => parts_last
    procedure :: swept_only => parts_swept_only
    procedure :: wants_rescue => parts_wants_rescue
    procedure :: wants_split => parts_wants_split
    procedure :: split => parts_split
    procedure :: unbounded => parts_unbounded
    procedure :: rescue_next => parts_rescue_next
    procedure :: taken => parts_taken
  end type remap_parts_t

contains

  !> Whether the next part is the first (its grid from `remap_part_target`).
  pure logical function parts_first(self)
    class(remap_parts_t), intent(in) :: self
    parts_first = self%ntaken == 0 .and. self%nleft == 0
  end function parts_first

  !> Whether the parts, the rest of the way split in two, stay within nmax.
  pure logical function parts_room(self)
    class(remap_parts_t), intent(in) :: self
    parts_room = self%ntaken + 2*max(self%nleft, 1) <= self%nmax
  end function parts_room

  !> Whether a part that does not arrive is the last the deck allows (it
  !> goes the rest of the way instead).
  pure logical function parts_last(self, arrived)
    class(remap_parts_t), intent(in) :: self
    logical, intent(in) :: arrived
    parts_last = .not. arrived .and. self%ntaken + 1 >= self%nmax
  end function parts_last

  !> Whether a part the swept faces can take (swept) is remapped by them
  !> only: nothing remapped where they would break a material's bounds, the
  !> part taken again shorter or rescued (`unbounded`).
  pure logical function parts_swept_only(self, swept)
    class(remap_parts_t), intent(in) :: self
    logical, intent(in) :: swept
    parts_swept_only = swept .and. (self%room() .or. self%hybrid)
  end function parts_swept_only

  !> Whether a part the swept faces cannot take (not swept), with no split
  !> left, is rescued around the nbroke cells that cannot take it of the
  !> nmoved that move.
  pure logical function parts_wants_rescue(self, swept, arrived, nbroke, nmoved)
    class(remap_parts_t), intent(in) :: self
    logical, intent(in) :: swept, arrived
    integer, intent(in) :: nbroke, nmoved
    parts_wants_rescue = .not. swept .and. (arrived .or. .not. self%room()) .and. self%hybrid .and. nbroke > 0 .and. &
                         nbroke < nmoved
  end function parts_wants_rescue

  !> Whether a part the swept faces cannot take, though its nodes stay
  !> within the bound, is split (shorter parts).
  pure logical function parts_wants_split(self, swept, arrived)
    class(remap_parts_t), intent(in) :: self
    logical, intent(in) :: swept, arrived
    parts_wants_split = .not. (swept .or. arrived) .and. self%room()
  end function parts_wants_split

  !> The parts split: the rest of the way in twice the parts (nleft, set
  !> by the caller where it was 0), the first part's nodes the same fraction
  !> of their way.
  pure subroutine parts_split(self)
    class(remap_parts_t), intent(inout) :: self
    self%nleft = 2*self%nleft
    self%nsplit = self%nsplit + 1
  end subroutine parts_split

  !> A part whose swept faces broke a material's bounds (nothing
  !> remapped): a rescue's stage 1 gives way to stage 3; else the first part
  !> again half as far, or the rest of the way in twice the parts, while
  !> there is room; else begin (true) a rescue of the part around the cells
  !> that broke a bound (the caller makes stage 1's grid).
  logical function parts_unbounded(self) result(begin)
    class(remap_parts_t), intent(inout) :: self
    begin = .false.
    if (self%rescue == 1) then
      self%rescue = 3
    else if (self%room()) then
      if (self%nleft == 0) self%fac = 0.5_wp*self%fac
      call self%split()
    else
      self%rescue = 1
      begin = .true.
    end if
  end function parts_unbounded

  !> A rescue's stage 1 (self%rescue 1) that the swept faces cannot take
  !> (not swept) gives way to stage 3, and one with no moving cell left
  !> (nmoved 0: every one is around those that cannot sweep) to stage 2:
  !> next, nothing remapped in this stage.
  logical function parts_rescue_next(self, swept, nmoved) result(next)
    class(remap_parts_t), intent(inout) :: self
    logical, intent(in) :: swept
    integer, intent(in) :: nmoved
    next = .false.
    if (self%rescue == 1 .and. .not. swept) then
      self%rescue = 3
      next = .true.
    else if (self%rescue == 1 .and. nmoved == 0) then
      self%rescue = 2
      next = .true.
    end if
  end function parts_rescue_next

  !> A part (or a rescue's stage) remapped: counted (a rescue's stage 1 is
  !> not a part; its stage 2 or 3 counts it as rescued); again: the
  !> rescue's stage 2 follows.
  logical function parts_taken(self) result(again)
    class(remap_parts_t), intent(inout) :: self
    if (self%rescue /= 1) then
      self%ntaken = self%ntaken + 1
      if (self%nleft > 0) self%nleft = self%nleft - 1
    end if
    if (self%rescue > 1) self%nrescue = self%nrescue + 1
    again = self%rescue == 1
    self%rescue = merge(2, 0, again)
  end function parts_taken
end module remap_parts
