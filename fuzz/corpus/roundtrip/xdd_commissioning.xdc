<?xml version="1.0"?>
<ISO15745ProfileContainer xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
  <ISO15745Profile>
    <ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen">
      <ApplicationLayers>
        <CANopenObjectList>
          <CANopenObject index="1800" name="TPDO communication parameter" objectType="9" subNumber="2">
            <CANopenSubObject subIndex="00" name="Highest sub-index supported" objectType="7" dataType="0005" accessType="ro" defaultValue="0x05"/>
            <CANopenSubObject subIndex="01" name="COB-ID used by TPDO" objectType="7" dataType="0007" accessType="rw" defaultValue="$NODEID+0x180" actualValue="0x40000190" denotation="tx"/>
          </CANopenObject>
          <CANopenObject index="2001" name="Gain" objectType="7" dataType="0008" accessType="rw" defaultValue="1.5" actualValue="2.25" PDOmapping="no"/>
          <CANopenObject index="2002" name="Time" objectType="7" dataType="000C" accessType="rw" defaultValue="12:3456"/>
        </CANopenObjectList>
      </ApplicationLayers>
      <NetworkManagement>
        <CANopenGeneralFeatures granularity="0" nrOfRxPDO="0" nrOfTxPDO="1" layerSettingServiceSlave="true"/>
        <CANopenMasterFeatures bootUpMaster="false"/>
        <deviceCommissioning nodeID="16" nodeName="axis 1" actualBaudRate="500 Kbps" networkNumber="1" networkName="line" CANopenManager="false"/>
      </NetworkManagement>
    </ProfileBody>
  </ISO15745Profile>
</ISO15745ProfileContainer>
