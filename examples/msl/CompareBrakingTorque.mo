within Modelica.Mechanics.Rotational.Examples;
model CompareBrakingTorque "Compare different braking torques"
  extends Modelica.Icons.Example;
  parameter SI.Torque tau_nominal=-100 "Nominal torque (if negative: braking)";
  parameter SI.AngularVelocity w_nominal(displayUnit="rpm")=100 "Nominal speed";
  parameter SI.AngularVelocity w0(min=Modelica.Constants.eps)=1 "Regularization below w0";
  Components.Inertia inertia1(
    J=1,
    phi(fixed=true, start=0),
    w(fixed=true, start=w_nominal))
    annotation (Placement(transformation(extent={{-10,50},{10,70}})));
  Components.Inertia inertia2(
    J=1,
    phi(fixed=true, start=0),
    w(fixed=true, start=w_nominal))
    annotation (Placement(transformation(extent={{-10,10},{10,30}})));
  Components.Inertia inertia3(
    J=1,
    phi(fixed=true, start=0),
    w(fixed=true, start=w_nominal))
    annotation (Placement(transformation(extent={{-10,-30},{10,-10}})));
  Components.Inertia inertia4(
    J=1,
    phi(fixed=true, start=0),
    w(fixed=true, start=w_nominal))
    annotation (Placement(transformation(extent={{-10,-70},{10,-50}})));
  Sources.SignTorque signTorque(
    tau_nominal=tau_nominal,
    reg=Modelica.Mechanics.Rotational.Types.Regularization.Linear,
    w0=w0)
    annotation (Placement(transformation(extent={{40,50},{20,70}})));
  Sources.LinearSpeedDependentTorque linearSpeedDependentTorque(
    tau_nominal=tau_nominal,
    TorqueDirection=false,
    w_nominal=w_nominal)
    annotation (Placement(transformation(extent={{40,10},{20,30}})));
  Sources.QuadraticSpeedDependentTorque quadraticSpeedDependentTorque(
    tau_nominal=tau_nominal,
    TorqueDirection=false,
    w_nominal=w_nominal)
    annotation (Placement(transformation(extent={{40,-30},{20,-10}})));
  Sources.InverseSpeedDependentTorque inverseSpeedDependentTorque(
    tau_nominal=tau_nominal,
    TorqueDirection=false,
    w_nominal=w_nominal,
    w0=w0)
    annotation (Placement(transformation(extent={{40,-70},{20,-50}})));
equation
  connect(signTorque.flange, inertia1.flange_a) annotation (Line(points={{20,60},{10,60}}));
  connect(linearSpeedDependentTorque.flange, inertia2.flange_a) annotation (Line(points={{20,20},{10,20}}));
  connect(quadraticSpeedDependentTorque.flange, inertia3.flange_a) annotation (Line(points={{20,-20},{10,-20}}));
  connect(inverseSpeedDependentTorque.flange, inertia4.flange_a) annotation (Line(points={{20,-60},{10,-60}}));
  annotation (experiment(StopTime=5, Interval=0.0001, Tolerance=1e-06), Documentation(info="<html>
<p>Four braking torque laws act on four equal inertias that start at the nominal speed.</p>
</html>"));
end CompareBrakingTorque;
