!> The CJ state a programmed burn runs at (`material_burn`), for the 3D
!> scene (`driver_scene`) and the 1D pre-run (`driver_prerun`).
module driver_burn
  use base_kinds, only: wp
  use base_strings, only: rtoa
  use base_errors, only: error_t, error_set, ERR_INPUT
  use material_table, only: material_t
  use material_burn, only: burn_cj
  use eos_jwl, only: jwl_t
  use io_log, only: log_t, log_line
  use driver_config, only: config_t
  implicit none
  private
  public :: burn_state, deck_problem

  !> What follows a deck mistake found while building the scene (an input
  !> error's `where` is the summary line of the refusal).
  character(len=*), parameter :: deck_problem = 'the deck has 1 problem(s); nothing was run'

contains

  !> The CJ state of explosive m, which a &detonation lights: from the
  !> unreacted state of its first region (rho0 and its energy), checked
  !> against its &material detonation_velocity (dv: that, or the CJ
  !> velocity), logged. False (nothing to light) if it fills no region.
  logical function burn_state(cfg, mat, m, log, rho0, dv, v_cj, err) result(lit)
    type(config_t), intent(in) :: cfg
    type(material_t), intent(in) :: mat
    integer, intent(in) :: m
    type(log_t), intent(in) :: log
    real(wp), intent(out) :: rho0, dv, v_cj
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: e0, d_cj, p_cj
    integer :: r
    character(len=100) :: who
    who = '&material '''//mat%name//''''
    rho0 = 0.0_wp; dv = 0.0_wp; v_cj = 1.0_wp
    r = findloc(cfg%regions%imat, m, dim=1)
    lit = r > 0
    if (.not. lit) then
      call log_line(log, 'detonation: '//trim(who)//' fills no region; nothing to light')
      return
    end if
    rho0 = cfg%regions(r)%density
    if (cfg%regions(r)%energy >= 0.0_wp) then
      e0 = cfg%regions(r)%energy
    else
      e0 = mat%eos%energy(rho0, cfg%regions(r)%pressure)
    end if
    d_cj = 0.0_wp
    select type (eos => mat%eos)
    type is (jwl_t)
      call burn_cj(eos, rho0, e0, d_cj, p_cj, v_cj)
    end select
    if (.not. d_cj > 0.0_wp) then
      call error_set(err, deck_problem, trim(who)//': its JWL has no Chapman-Jouguet state from density '//rtoa(rho0)// &
                     ' and energy '//rtoa(e0)//' (no positive Hugoniot pressure)', ERR_INPUT)
      return
    end if
    dv = cfg%materials(m)%detonation_velocity
    if (dv > 0.0_wp .and. abs(dv/d_cj - 1.0_wp) > 0.05_wp) then
      call error_set(err, deck_problem, trim(who)//': detonation_velocity = '//rtoa(dv)//' is not within 5 % of '// &
                     'the CJ velocity '//rtoa(d_cj)//' of its JWL from density '//rtoa(rho0)//' and energy '// &
                     rtoa(e0)//' (the products would not sustain that front); give 0 for the CJ velocity', ERR_INPUT)
      return
    end if
    if (.not. dv > 0.0_wp) dv = d_cj
    call log_line(log, 'detonation: '//trim(who)//' from density '//rtoa(rho0)//', energy '//rtoa(e0)// &
                  ': CJ velocity '//rtoa(d_cj)//', pressure '//rtoa(p_cj)//', relative volume '//rtoa(v_cj)// &
                  '; programmed burn at D = '//rtoa(dv)//' over '//rtoa(cfg%materials(m)%burn_width)//' cells')
  end function burn_state
end module driver_burn
